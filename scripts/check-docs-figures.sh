#!/usr/bin/env bash
# Re-measures the figures README.md and docs/ state and prints each beside today's value, so
# a stale figure is caught before a release. Every measured number in the docs has a row
# here with the command that reproduces it (on the bundled sample or Debian's
# assimp-testmodels).
#
#   scripts/check-docs-figures.sh [--cheap] [--build DIR]
#
# --cheap  only the figures that take seconds and do not depend on the machine (CI runs
#          these: ctest docs.figures).
# Exit status: 1 when a figure of an exact kind no longer matches, or a documented text is
# no longer in its file (the docs changed: update the row); timings are printed beside the
# documented value and flagged when they differ by more than 2x, but never fail the run
# (they depend on the machine).
set -uo pipefail
cd "$(dirname "$0")/.."

cheap=0
build=build
while [ $# -gt 0 ]; do
  case "$1" in
    --cheap) cheap=1 ;;
    --build) build=$2; shift ;;
    *) echo "usage: $0 [--cheap] [--build DIR]" >&2; exit 2 ;;
  esac
  shift
done
motionlod=$build/bin/motionlod
[ -x "$motionlod" ] || { echo "error: $motionlod: not built (cmake --build $build)" >&2; exit 2; }
models=${MLOD_ASSIMP_MODELS:-/usr/share/assimp/models}
sample=resources/sample/cmu_01_01_excerpt.bvh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
stale=0

# exact FILE TEXT TODAY [WHAT]: TEXT (the figure as the docs write it) must be in FILE and
# equal TODAY (today's value, formatted the same way).
exact() {
  local file=$1 text=$2 today=$3 what=${4:-}
  local state=ok
  if ! grep -qF -- "$text" "$file"; then
    state="NOT IN FILE"
    stale=1
  elif [ "$text" != "$today" ]; then
    state=STALE
    stale=1
  fi
  printf '%-12s %-24s documented %-14s today %-14s %s\n' "$state" "$file" "$text" "$today" "$what"
}

# measured LABEL FACTOR FILE TEXT DOCUMENTED TODAY [WHAT]: a figure that depends on the
# machine or moves a little with every change; informational, flagged "LABEL >xFACTOR" when
# today's value differs from the documented one by more than FACTOR either way.
measured() {
  local label=$1 factor=$2 file=$3 text=$4 documented=$5 today=$6 what=${7:-}
  local state=$label
  grep -qF -- "$text" "$file" || { state="NOT IN FILE"; stale=1; }
  if [ "$state" = "$label" ] && awk -v a="$documented" -v b="$today" -v f="$factor" 'BEGIN { exit !(b > f * a || f * b < a) }'; then
    state="$label >x$factor"
  fi
  printf '%-12s %-24s documented %-14s today %-14s %s\n' "$state" "$file" "$documented" "$today" "$what"
}
# timing FILE TEXT SECONDS_DOCUMENTED SECONDS_TODAY [WHAT]: flagged beyond 2x.
timing() { measured timing 2 "$@"; }
# approx FILE TEXT DOCUMENTED TODAY [WHAT]: a size, flagged beyond 10%.
approx() { measured size 1.1 "$@"; }

fmt() { # printf format, value
  LC_ALL=C printf "$1" "$2"
}
thousands() { # 3014 -> 3,014
  echo "$1" | sed ':a;s/\B[0-9]\{3\}\>/,&/;ta'
}

echo "== Table 1 of the sample (docs/user-guide.md): motionlod simplify $sample --unit-scale cmu --threshold 5,50,100,300 --json"
"$motionlod" simplify "$sample" --unit-scale cmu --threshold 5,50,100,300 --json >"$work/table1.json" || exit 1
row_percent="| Simplified joints % | 0.0"
row_error="| Max joint position error (cm) | 0"
for i in 0 1 2 3; do
  row_percent="$row_percent | $(fmt %.1f "$(jq ".thresholds[$i].simplified_joint_percent" "$work/table1.json")")"
  row_error="$row_error | $(fmt %.3f "$(jq ".thresholds[$i].max_joint_position_error_cm" "$work/table1.json")")"
done
exact docs/user-guide.md "$row_percent |" "$row_percent |" "Table 1, simplified %"
grep -qF -- "$row_percent |" docs/user-guide.md || grep -F "| Simplified joints % |" docs/user-guide.md | head -1 | sed 's/^/             documented: /'
exact docs/user-guide.md "$row_error |" "$row_error |" "Table 1, max joint position error"
grep -qF -- "$row_error |" docs/user-guide.md || grep -F "| Max joint position error (cm) |" docs/user-guide.md | head -1 | sed 's/^/             documented: /'
frames=$(jq .frames "$work/table1.json")
exact docs/user-guide.md "$(fmt %d "$frames") frames at 120 fps" "$frames frames at $(fmt %.0f "$(jq .fps "$work/table1.json")") fps" "the sample's length"

echo "== BCN_Epileptic re-imported from its glTF export (docs/gltf-extension.md): motionlod export X/BCN_Epileptic.X --plugin gltf; motionlod info --json"
if "$motionlod" export "$models/X/BCN_Epileptic.X" --plugin gltf -o "$work/bcn.glb" --quiet >/dev/null 2>"$work/export.err" &&
   "$motionlod" info "$work/bcn.glb" --json >"$work/bcn.json" 2>/dev/null; then
  mesh='[.meshes[]] | sort_by(-.vertices) | .[0]'
  vertices=$(thousands "$(jq "$mesh | .vertices" "$work/bcn.json")")
  triangles=$(thousands "$(jq "$mesh | .triangles" "$work/bcn.json")")
  bones=$(jq "$mesh | .bones" "$work/bcn.json")
  parts=$(jq "$mesh | .parts" "$work/bcn.json")
  exact docs/gltf-extension.md "its $vertices vertices," "its $vertices vertices," "finest level's vertices"
  exact docs/gltf-extension.md "$triangles triangles, $bones bones and $parts parts" \
    "$triangles triangles, $bones bones and $parts parts" "finest level's triangles, bones, parts"
else
  echo "FAILED       export or info of BCN_Epileptic: $(cat "$work/export.err")"
  stale=1
fi

echo "== What Assimp reads of a motion-only glTF (docs/gltf-extension.md): motionlod export 01_01.bvh --plugin gltf; assimp info FILE -r"
if command -v assimp >/dev/null; then
  if "$motionlod" export "$models/BVH/01_01.bvh" --plugin gltf -o "$work/motion.glb" --quiet >/dev/null 2>"$work/export.err"; then
    assimp info "$work/motion.glb" -r >"$work/assimp.txt" 2>&1
    nodes=$(sed -n 's/^Nodes: *\([0-9]*\)$/\1/p' "$work/assimp.txt")
    animations=$(sed -n 's/^Animations: *\([0-9]*\)$/\1/p' "$work/assimp.txt")
    exact docs/gltf-extension.md "(38 nodes and 4 animations for CMU 01_01)" \
      "($nodes nodes and $animations animations for CMU 01_01)" "assimp info -r of a motion-only file"
    assimp info "$work/motion.glb" >"$work/assimp-plain.txt" 2>&1
    if grep -qF "No materials remaining" "$work/assimp-plain.txt"; then
      exact docs/gltf-extension.md '"No materials remaining"' '"No materials remaining"' "assimp info without -r"
    else
      exact docs/gltf-extension.md '"No materials remaining"' "(reads)" "assimp info without -r no longer fails"
    fi
  else
    echo "FAILED       export of 01_01: $(cat "$work/export.err")"
    stale=1
  fi
else
  echo "skipped      assimp (package assimp-utils) is not installed"
fi

if [ "$cheap" -eq 0 ]; then
  echo "== The paper's Figure 12 (docs/user-guide.md, README.md): motionlod bench-crowd BCN_Epileptic.X --scene --motion 01_03.bvh --skinning cpu --agents 1000 --frames 60 --threads 1 --repetitions 3 --json"
  if "$motionlod" bench-crowd "$models/X/BCN_Epileptic.X" --scene --motion "$models/BVH/01_03.bvh" --skinning cpu --agents 1000 \
       --frames 60 --threads 1 --repetitions 3 --json >"$work/scene.json" 2>"$work/scene.err"; then
    agents=$(jq -r '[.levels[1:][] | .agents | tostring] | join(", ")' "$work/scene.json")
    exact docs/user-guide.md "130, 522 and 324 agents" "$(echo "$agents" | sed 's/, \([0-9]*\)$/ and \1/') agents" "agents per level"
    for c in none skeletal mesh both; do
      joints=$(thousands "$(jq ".configurations.$c.joints_evaluated | round" "$work/scene.json")")
      row=$(grep -F "| $c | " docs/user-guide.md | head -1)
      exact docs/user-guide.md "$(echo "$row" | awk -F' [|] ' '{print $5}')" "$joints" "$c: joints evaluated"
      timing docs/user-guide.md "| $c | " "$(echo "$row" | awk -F' [|] ' '{print $2}')" \
        "$(fmt %.2f "$(jq ".configurations.$c.frame_ms" "$work/scene.json")")" "$c: frame ms"
    done
  else
    echo "FAILED       bench-crowd --scene: $(cat "$work/scene.err")"
    stale=1
  fi

  echo "== Peak memory (docs/user-guide.md): /usr/bin/time -f %M motionlod info|simplify --threshold 50 on CMU 01_01 repeated"
  long_bvh() { # FRAMES OUT: CMU 01_01's frames repeated to FRAMES frames
    awk -v n="$1" '
      /^Frames:/ { print "Frames: " n; next }
      !m { print; if ($0 ~ /^Frame Time:/) m = 1; next }
      { f[c++] = $0 }
      END { for (i = 0; i < n; i++) print f[i % c] }' "$models/BVH/01_01.bvh" >"$2"
  }
  peak_mib() { # COMMAND...: the peak resident set in MiB
    /usr/bin/time -f %M -o "$work/rss" "$@" >/dev/null 2>&1 || { echo failed; return; }
    awk '{ printf "%.0f", $1 / 1024 }' "$work/rss"
  }
  doc_mib() { # ROW COLUMN: the MiB documented in the memory table's row, column 3 or 4
    grep -F -- "| $1 |" docs/user-guide.md | head -1 | awk -F' [|] ' -v c="$2" '{ sub(/ MiB.*/, "", $c); print $c }'
  }
  for row in "sample excerpt (480 frames)|" "50,000 frames (36 MiB BVH)|50000" "100,000 frames (72 MiB BVH)|100000" \
             "200,000 frames (143 MiB BVH)|200000"; do
    text=${row%%|*}
    frames=${row#*|}
    input=$sample
    [ -n "$frames" ] && { input=$work/long.bvh; long_bvh "$frames" "$input"; }
    timing docs/user-guide.md "| $text |" "$(doc_mib "$text" 3)" \
      "$(peak_mib "$motionlod" info "$input" --unit-scale cmu)" "info MiB, $text"
    timing docs/user-guide.md "| $text |" "$(doc_mib "$text" 4)" \
      "$(peak_mib "$motionlod" simplify "$input" --unit-scale cmu --threshold 50)" "simplify MiB, $text"
  done
  rm -f "$work/long.bvh"

  echo "== Package sizes (docs/install.md): cpack -G \"DEB;TGZ\" in $build"
  if (cd "$build" && cpack -G "DEB;TGZ" -B "$work/pkg" >/dev/null 2>"$work/cpack.err"); then
    deb=$(ls "$work"/pkg/*.deb | head -1)
    tgz=$(ls "$work"/pkg/*.tar.gz | head -1)
    line=$(grep -F "the \`.deb\` is" docs/install.md | head -1)
    approx docs/install.md "the \`.deb\` is" "$(echo "$line" | sed -n 's/.*the `.deb` is \([0-9.]*\) MB.*/\1/p')" \
      "$(fmt %.1f "$(stat -c %s "$deb" | awk '{ print $1 / 1e6 }')")" ".deb MB"
    approx docs/install.md "the \`.deb\` is" "$(echo "$line" | sed -n 's/.*installs \([0-9,]*\) KiB.*/\1/p' | tr -d ,)" \
      "$(dpkg-deb -f "$deb" Installed-Size)" ".deb installed KiB"
    approx docs/install.md "the \`.tar.gz\` is" "$(echo "$line" | sed -n 's/.*the `.tar.gz` is \([0-9.]*\) MB.*/\1/p')" \
      "$(fmt %.1f "$(stat -c %s "$tgz" | awk '{ print $1 / 1e6 }')")" ".tar.gz MB"
  else
    echo "FAILED       cpack: $(tail -3 "$work/cpack.err")"
    stale=1
  fi

  echo "== Export times (docs/farm.md): /usr/bin/time motionlod export ... (one job at a time)"
  t() { # seconds of one export
    local start end
    start=$(date +%s.%N)
    "$motionlod" export "$@" --quiet >/dev/null 2>&1 || { echo "failed"; return; }
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
  }
  doc_time() { # the seconds documented in the farm.md row that contains TEXT
    grep -F -- "$1" docs/farm.md | head -1 | sed -n 's/.*| \([0-9.]*\) s |$/\1/p'
  }
  for row in "CMU \`BVH/01_01.bvh\` (2,752 frames, 38 joints, no mesh) → \`bundle\`|$models/BVH/01_01.bvh --unit-scale cmu --plugin bundle -o $work/a.mlodb" \
             "CMU \`BVH/01_03.bvh\` → \`gltf\`|$models/BVH/01_03.bvh --unit-scale cmu --plugin gltf -o $work/b.glb" \
             "\`X/BCN_Epileptic.X\` (54 joints, 5,126 triangles, 100 frames) → \`gltf\`|$models/X/BCN_Epileptic.X --plugin gltf -o $work/c.glb" \
             "\`X/BCN_Epileptic.X\` → \`bundle\`|$models/X/BCN_Epileptic.X --plugin bundle -o $work/d.mlodb"; do
    text=${row%%|*}
    # shellcheck disable=SC2086
    timing docs/farm.md "$text" "$(doc_time "$text")" "$(t ${row#*|})" "${text:0:40}"
  done
fi

echo
if [ "$stale" -ne 0 ]; then
  echo "check-docs-figures: some documented figures are stale or missing (see above)"
  exit 1
fi
echo "check-docs-figures: every exact figure matches"
