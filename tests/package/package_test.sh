#!/usr/bin/env bash
# The package tests (ctest label "package"): cpack on the existing build tree, then what a
# technical artist or an engine programmer does with the packages, run from where they were
# unpacked. Every step says what failed; the first failure ends the step with status 1.
#
#   package_test.sh build BUILD_DIR OUT CPACK
#   package_test.sh tgz   BUILD_DIR OUT LIBDIR PNG_STATS XVFB_RUN
#   package_test.sh deb   BUILD_DIR OUT LIBDIR
#   package_test.sh sdk   BUILD_DIR OUT SOURCE_DIR CMAKE
#
# BUILD_DIR is the configured build tree, OUT the folder the packages go to (the "build"
# step empties it first), LIBDIR CMAKE_INSTALL_LIBDIR (lib/x86_64-linux-gnu for a /usr
# prefix), PNG_STATS the mlod_png_stats helper.
set -euo pipefail

step=$1
build=$2
out=$3
shift 3

fail() {
  echo "FAIL [$step]: $*" >&2
  exit 1
}
say() { echo "[$step] $*"; }

sample_rel=share/motionlod/sample/cmu_01_01_excerpt.bvh
# A clean environment: no plugin path pointing into the build tree, our own HOME.
scratch_env() { # folder
  mkdir -p "$1/home" "$1/xdg"
  chmod 700 "$1/xdg"
  export HOME="$1/home" XDG_RUNTIME_DIR="$1/xdg"
  unset MOTIONLOD_PLUGIN_PATH
}

the_package() { # pattern
  local matches=("$out"/$1)
  [ ${#matches[@]} -eq 1 ] && [ -f "${matches[0]}" ] || fail "expected one $1 in $out, found: ${matches[*]}"
  echo "${matches[0]}"
}

# Files both packages must hold, relative to the install prefix.
expected_files() { # libdir
  cat <<EOF
bin/motionlod
bin/motionlod-studio
$sample_rel
share/applications/motionlod-studio.desktop
share/icons/hicolor/16x16/apps/motionlod-studio.png
share/icons/hicolor/256x256/apps/motionlod-studio.png
share/icons/hicolor/scalable/apps/motionlod-studio.svg
share/metainfo/org.motionlod.Studio.metainfo.xml
share/man/man1/motionlod.1.gz
share/man/man1/motionlod-studio.1.gz
share/motionlod/farm/kubernetes-indexed-job.yaml
share/motionlod/farm/motionlod.sub
share/doc/motionlod/LICENSE
share/doc/motionlod/THIRD-PARTY-NOTICES.md
share/doc/motionlod/changelog.gz
share/doc/motionlod/copyright
include/motionlod/runtime/pose_evaluator.h
include/motionlod/runtime/lod_clip.h
$1/libmlod_runtime.a
$1/cmake/MotionLODRuntime/MotionLODRuntimeConfig.cmake
$1/cmake/MotionLODRuntime/MotionLODRuntimeConfigVersion.cmake
$1/cmake/MotionLODRuntime/MotionLODRuntimeTargets.cmake
EOF
}

check_files() { # root libdir
  local missing=0
  while read -r file; do
    [ -f "$1/$file" ] || { echo "missing: $file" >&2; missing=1; }
  done < <(expected_files "$2")
  # Every exporter plugin the build made (its plugin folder mirrors the install layout).
  local plugin
  for plugin in "$build/$2"/motionlod/plugins/*.so; do
    [ -e "$plugin" ] || continue
    [ -f "$1/$2/motionlod/plugins/${plugin##*/}" ] || { echo "missing plugin: ${plugin##*/}" >&2; missing=1; }
  done
  [ $missing -eq 0 ] || fail "files missing from the package"
  # Executables and plugins must not look for anything in the build tree.
  local binary
  for binary in "$1"/bin/* "$1/$2"/motionlod/plugins/*.so; do
    [ -e "$binary" ] || continue
    if readelf -d "$binary" | grep -E 'R(UN)?PATH' | grep -qF "$build"; then
      fail "$binary: its RUNPATH names the build tree: $(readelf -d "$binary" | grep -E 'R(UN)?PATH')"
    fi
  done
}

# motionlod from ROOT: --version, simplify on the installed sample equal to the build tree's.
check_cli() { # root
  local cli="$1/bin/motionlod"
  local version
  version=$("$cli" --version) || fail "$cli --version failed"
  say "$version"
  [ "$version" = "$("$build/bin/motionlod" --version)" ] || fail "version differs from the build tree's"
  # Every exporter the build tree has, loaded from the package's own plugin folder; none failed.
  "$cli" plugins --json > "$1.plugins.json" || fail "$cli plugins --json failed"
  [ "$(jq '.failed | length' "$1.plugins.json")" = 0 ] || fail "plugins failed to load: $(jq -c '.failed' "$1.plugins.json")"
  local ids expected_ids outside
  ids=$(jq -r '[.plugins[].id] | sort | join(" ")' "$1.plugins.json")
  expected_ids=$("$build/bin/motionlod" plugins --json | jq -r '[.plugins[].id] | sort | join(" ")')
  [ -n "$ids" ] && [ "$ids" = "$expected_ids" ] || fail "plugins from the package: '$ids'; the build tree has '$expected_ids'"
  outside=$(jq -r --arg root "$1/" '.plugins[] | select(.file | startswith($root) | not) | .file' "$1.plugins.json")
  [ -z "$outside" ] || fail "plugins loaded from outside the package: $outside"
  say "plugins: $ids"
  # Each exporter runs from the package and writes what the build tree's writes.
  local id suffix
  mkdir -p "$1.exports"
  for id in $ids; do
    suffix=$(jq -r --arg id "$id" '.plugins[] | select(.id == $id) | .suffixes[0]' "$1.plugins.json")
    "$cli" export "$1/$sample_rel" --unit-scale cmu --plugin "$id" -o "$1.exports/package.$suffix" > /dev/null ||
      fail "$cli export --plugin $id failed"
    "$build/bin/motionlod" export "$1/$sample_rel" --unit-scale cmu --plugin "$id" -o "$1.exports/build.$suffix" > /dev/null
    cmp "$1.exports/package.$suffix" "$1.exports/build.$suffix" || fail "export --plugin $id differs from the build tree's"
  done
  "$cli" simplify "$1/$sample_rel" --unit-scale cmu --threshold 5,50,100,300 --json > "$1.simplify.json" ||
    fail "$cli simplify on the installed sample failed"
  "$build/bin/motionlod" simplify "$1/$sample_rel" --unit-scale cmu --threshold 5,50,100,300 --json > "$1.expected.json"
  diff <(jq -S 'del(.seconds, .file)' "$1.expected.json") <(jq -S 'del(.seconds, .file)' "$1.simplify.json") ||
    fail "simplify from the package differs from the build tree's"
  say "simplify: $(jq -c '[.thresholds[] | {threshold, simplified_joint_percent}]' "$1.simplify.json")"
}

case $step in
build)
  cpack=$1
  rm -rf "$out"
  mkdir -p "$out"
  # Both generators in one run, from the existing build tree (cpack builds nothing new
  # when the tree is up to date).
  "$cpack" --config "$build/CPackConfig.cmake" -G "TGZ;DEB" -B "$out" > "$out/cpack.log" 2>&1 ||
    { cat "$out/cpack.log" >&2; fail "cpack failed"; }
  the_package '*.deb' > /dev/null
  the_package '*.tar.gz' > /dev/null
  ls -l "$out"/*.deb "$out"/*.tar.gz
  ;;

tgz)
  libdir=$1 png_stats=$2 xvfb_run=$3
  tgz=$(the_package '*.tar.gz')
  # Unpacked into a folder with a space in its name, far from the build tree.
  unpacked="$out/unpacked tgz"
  rm -rf "$unpacked" && mkdir -p "$unpacked"
  tar -xzf "$tgz" -C "$unpacked"
  root=$(find "$unpacked" -mindepth 1 -maxdepth 1 -type d)
  [ -n "$root" ] && [ -x "$root/bin/motionlod" ] || fail "no bin/motionlod in $tgz"
  check_files "$root" "$libdir"
  scratch_env "$out/env-tgz"
  check_cli "$root"

  # Metadata as the desktop and software centres read it.
  desktop-file-validate "$root/share/applications/motionlod-studio.desktop" || fail "desktop entry invalid"
  appstreamcli validate --no-net "$root/share/metainfo/org.motionlod.Studio.metainfo.xml" ||
    fail "AppStream metadata invalid"
  for size in 16 22 24 32 48 64 128 256; do
    read -r w h colours < <("$png_stats" "$root/share/icons/hicolor/${size}x${size}/apps/motionlod-studio.png") ||
      fail "icon ${size}x${size} unreadable"
    [ "$w" = "$size" ] && [ "$h" = "$size" ] || fail "icon ${size}x${size} is ${w}x${h}"
  done
  # The man pages render without a warning.
  for page in motionlod motionlod-studio; do
    man_warnings=$(MANWIDTH=80 man --warnings -l "$root/share/man/man1/$page.1.gz" 2>&1 > /dev/null)
    [ -z "$man_warnings" ] || fail "$page man page warnings: $man_warnings"
  done

  # The studio, from the unpacked tree, on its installed sample, under Xvfb.
  shot="$out/studio-tgz.png"
  rm -f "$shot"
  "$xvfb_run" -a -s "-screen 0 1600x1000x24" "$root/bin/motionlod-studio" --sample --screenshot "$shot" ||
    fail "motionlod-studio --sample --screenshot failed"
  read -r w h colours < <("$png_stats" "$shot") || fail "no screenshot written"
  say "screenshot ${w}x${h}, $colours colours"
  [ "$w" -ge 800 ] && [ "$h" -ge 600 ] || fail "screenshot is only ${w}x${h}"
  [ "$colours" -ge 256 ] || fail "screenshot looks blank: $colours colours"
  # It really opened the unpacked sample (not the source tree's): a broken copy there fails.
  cp "$root/$sample_rel" "$out/sample.bak"
  echo "not a BVH" > "$root/$sample_rel"
  if "$xvfb_run" -a -s "-screen 0 1600x1000x24" "$root/bin/motionlod-studio" --sample --screenshot "$out/broken.png" \
    > "$out/broken.log" 2>&1; then
    cp "$out/sample.bak" "$root/$sample_rel"
    fail "motionlod-studio --sample did not read the unpacked tree's sample"
  fi
  cp "$out/sample.bak" "$root/$sample_rel"
  ;;

deb)
  libdir=$1
  deb=$(the_package '*.deb')
  info=$(dpkg-deb -I "$deb")
  echo "$info"
  depends=$(dpkg-deb -f "$deb" Depends)
  # dpkg-shlibdeps filled Depends from the binaries' NEEDED entries.
  depends_names=$(tr ',|' '\n\n' <<< "$depends" | sed -E 's/^ +//; s/ .*//')
  for package in libc6 libstdc++6 libqt6core6 libqt6gui6 libqt6widgets6 libqt6charts6 libassimp5 libopenmesh1; do
    grep -qxF "$package" <<< "$depends_names" || fail "Depends lacks $package: $depends"
  done
  [ "$(dpkg-deb -f "$deb" Package)" = motionlod ] || fail "package name"
  [ -n "$(dpkg-deb -f "$deb" Maintainer)" ] && [ -n "$(dpkg-deb -f "$deb" Section)" ] ||
    fail "Maintainer or Section empty"
  extracted="$out/deb root"
  rm -rf "$extracted" && mkdir -p "$extracted"
  dpkg-deb -x "$deb" "$extracted"
  root="$extracted/usr"
  check_files "$root" "$libdir"
  # Nothing outside /usr.
  others=$(find "$extracted" -mindepth 1 -maxdepth 1 ! -name usr)
  [ -z "$others" ] || fail "files outside /usr: $others"
  scratch_env "$out/env-deb"
  check_cli "$root"
  ;;

sdk)
  source=$1 cmake=$2
  tgz=$(the_package '*.tar.gz')
  prefix="$out/sdk prefix"
  rm -rf "$prefix" "$out/sdk-build" && mkdir -p "$prefix"
  tar -xzf "$tgz" -C "$prefix" --strip-components=1
  # An engine's own build finds the runtime in the unpacked package and links it.
  "$cmake" -S "$source/tests/package/sdk_consumer" -B "$out/sdk-build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" > "$out/sdk-configure.log" 2>&1 ||
    { cat "$out/sdk-configure.log" >&2; fail "find_package(MotionLODRuntime) failed"; }
  grep -q "MotionLODRuntime_DIR:PATH=$prefix" "$out/sdk-build/CMakeCache.txt" ||
    fail "MotionLODRuntime found somewhere else than the package: $(grep MotionLODRuntime_DIR "$out/sdk-build/CMakeCache.txt")"
  "$cmake" --build "$out/sdk-build" > "$out/sdk-build.log" 2>&1 ||
    { cat "$out/sdk-build.log" >&2; fail "the consumer did not build against the package"; }
  "$out/sdk-build/consumer" || fail "the consumer linked against the package failed"
  ;;

*)
  fail "unknown step"
  ;;
esac
say "ok"
