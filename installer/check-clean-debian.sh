#!/usr/bin/env bash
# Release check (root, network to a Debian mirror; not part of CI): installs the .deb into
# a fresh minimal Debian 12 (debootstrap --variant=minbase) with apt, which fetches exactly
# what the package's Depends names, and runs what a technical artist runs first:
# motionlod --version, plugins (none may fail), simplify and every exporter on the
# installed sample, and motionlod-studio --sample --screenshot under Xvfb.
#
#   bash installer/check-clean-debian.sh build-pkg/package-test/motionlod_0.1.0_amd64.deb [WORKDIR]
#
# The root file system is left in WORKDIR (default: a new temporary folder) for a look.
set -euo pipefail

deb=$(realpath "$1")
root=${2:-$(mktemp -d /tmp/motionlod-clean-debian.XXXXXX)}
mirror=${MLOD_DEBIAN_MIRROR:-http://deb.debian.org/debian}
[ "$(id -u)" -eq 0 ] || { echo "check-clean-debian: run as root (debootstrap, chroot)" >&2; exit 1; }
command -v debootstrap > /dev/null || { echo "check-clean-debian: apt-get install debootstrap" >&2; exit 1; }

if [ ! -x "$root/usr/bin/apt-get" ]; then
  echo "== debootstrap bookworm (minbase) into $root"
  debootstrap --variant=minbase bookworm "$root" "$mirror" > "$root.debootstrap.log" 2>&1 ||
    { tail -20 "$root.debootstrap.log" >&2; exit 1; }
fi
cp "$deb" "$root/tmp/"
cp /etc/resolv.conf "$root/etc/resolv.conf"
mount -t proc proc "$root/proc"
mount --bind /dev "$root/dev"
trap 'umount "$root/proc" "$root/dev"' EXIT

chroot "$root" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEB="/tmp/${deb##*/}" /bin/bash -euo pipefail -c '
export DEBIAN_FRONTEND=noninteractive HOME=/tmp XDG_RUNTIME_DIR=/tmp/xdg
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
echo "== apt install $DEB (no recommends)"
apt-get update -qq
before=$(dpkg-query -W | wc -l)
apt-get install -y -qq --no-install-recommends "$DEB" > /tmp/install.log
echo "   $(( $(dpkg-query -W | wc -l) - before )) packages installed; $(dpkg-query -W -f="\${Installed-Size}" motionlod) KiB for motionlod"
echo "== test tools: jq, xvfb, xauth"
apt-get install -y -qq --no-install-recommends jq xvfb xauth > /tmp/tools.log
motionlod --version
motionlod plugins --json > /tmp/plugins.json
[ "$(jq ".failed | length" /tmp/plugins.json)" = 0 ] || { echo "plugins failed to load:"; jq ".failed" /tmp/plugins.json; exit 1; }
echo "   plugins: $(jq -r "[.plugins[].id] | join(\" \")" /tmp/plugins.json)"
sample=/usr/share/motionlod/sample/cmu_01_01_excerpt.bvh
motionlod simplify "$sample" --unit-scale cmu --threshold 5,50,100,300 | sed -n 5,7p
cd /tmp
for id in $(jq -r ".plugins[].id" /tmp/plugins.json); do
  out=/tmp/sample-$id.$(jq -r --arg id "$id" ".plugins[] | select(.id == \$id) | .suffixes[0]" /tmp/plugins.json)
  motionlod export "$sample" --unit-scale cmu --plugin "$id" -o "$out" > /dev/null
  echo "   export --plugin $id: $out, $(stat -c %s "$out") bytes"
done
echo "== motionlod-studio --sample --screenshot under Xvfb"
xvfb-run -a -s "-screen 0 1600x1000x24" motionlod-studio --sample --screenshot /tmp/studio.png
echo "   $(stat -c %s /tmp/studio.png) bytes"
'
echo "== ok: $root/tmp/studio.png"
