#!/usr/bin/env bash
# The farm test (ctest label "farm"): runs the shipped scheduler specs the way the
# schedulers would, on this machine. For each of installer/farm/kubernetes-indexed-job.yaml
# and installer/farm/motionlod.sub it reads the command line and the number of shards from
# the file itself, substitutes each index as the scheduler does ($(JOB_COMPLETION_INDEX),
# $(Process)), starts every shard at once, and checks against one single-process run of the
# same manifest:
#   - every job of the manifest is exported by exactly one shard, and succeeds;
#   - the output files are byte-identical to the single run's.
#
#   farm_test.sh MOTIONLOD SOURCE_DIR OUT MODELS
set -euo pipefail

motionlod=$1
source=$2
out=$3
models=$4

fail() {
  echo "FAIL [farm]: $*" >&2
  exit 1
}
say() { echo "[farm] $*"; }

rm -rf "$out"
mkdir -p "$out"
export HOME="$out/home" XDG_RUNTIME_DIR="$out/xdg" QT_QPA_PLATFORM=offscreen
mkdir -p "$HOME" "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
unset MOTIONLOD_PLUGIN_PATH

# A small motion library: real mocap and a skinned character through every exporter, more
# jobs than shards so that some shards get several. Inputs are absolute, outputs relative to
# the manifest's folder (each run gets its own folder).
cat > "$out/manifest.json" <<EOF
{"jobs": [
  {"input": "$models/BVH/01_01.bvh", "plugin": "bundle", "output": "out/01_01.mlodb", "unit_scale": "cmu", "options": {}},
  {"input": "$models/BVH/01_01.bvh", "plugin": "example", "output": "out/01_01.summary.json", "unit_scale": "cmu", "options": {}},
  {"input": "$models/BVH/01_01.bvh", "plugin": "gltf", "output": "out/01_01.glb", "unit_scale": "cmu", "options": {}},
  {"input": "$models/BVH/01_01.bvh", "plugin": "report", "output": "out/01_01.html", "unit_scale": "cmu", "options": {}},
  {"input": "$models/BVH/01_03.bvh", "plugin": "gltf", "output": "out/01_03.gltf", "unit_scale": "cmu", "options": {"pretty": true}},
  {"input": "$models/BVH/01_03.bvh", "plugin": "example", "output": "out/01_03.summary.json", "unit_scale": "cmu", "options": {"indent": false}},
  {"input": "$models/BVH/01_01.bvh", "plugin": "bundle", "output": "out/01_01-motion.mlodb", "unit_scale": "cmu", "levels": [0, 2], "options": {"manifest": false}},
  {"input": "$models/X/BCN_Epileptic.X", "plugin": "gltf", "output": "out/BCN_Epileptic.glb", "unit_scale": "m", "options": {}},
  {"input": "$source/resources/sample/cmu_01_01_excerpt.bvh", "plugin": "report", "output": "out/sample.csv", "unit_scale": "cmu", "options": {}},
  {"input": "$source/resources/sample/cmu_01_01_excerpt.bvh", "plugin": "example", "output": "out/sample.summary.json", "unit_scale": "cmu", "options": {}},
  {"input": "$models/BVH/01_03.bvh", "plugin": "report", "output": "out/01_03.json", "unit_scale": "cmu", "options": {}}
]}
EOF
job_count=$(jq '.jobs | length' "$out/manifest.json")

# The reference: one process, every job.
# batch writes into existing folders only (on a farm: the shared library's output folder).
mkdir -p "$out/single/out"
cp "$out/manifest.json" "$out/single/manifest.json"
"$motionlod" batch "$out/single/manifest.json" --json > "$out/single.json" || fail "the single-process batch failed"
[ "$(jq '.succeeded' "$out/single.json")" = "$job_count" ] || fail "the single run did not export all $job_count jobs"
say "single process: $job_count jobs in $(jq '.seconds' "$out/single.json") s"

# run_shards NAME SHARDS COMMAND-TEMPLATE...: the template's words, with @INDEX@ for the
# shard index, @MANIFEST@ for the manifest and @MOTIONLOD@ for the program; every shard
# starts at once, in its own copy of the folder layout, and writes its JSON report.
run_shards() {
  local name=$1 shards=$2
  shift 2
  local dir="$out/$name"
  mkdir -p "$dir/out"
  cp "$out/manifest.json" "$dir/manifest.json"
  local pids=() i word command
  for ((i = 0; i < shards; ++i)); do
    command=()
    for word in "$@"; do
      word=${word//@INDEX@/$i}
      word=${word//@MANIFEST@/$dir/manifest.json}
      word=${word//@MOTIONLOD@/$motionlod}
      command+=("$word")
    done
    "${command[@]}" > "$dir/shard-$i.json" 2> "$dir/shard-$i.err" &
    pids+=($!)
  done
  for ((i = 0; i < shards; ++i)); do
    wait "${pids[$i]}" || fail "$name: shard $i of $shards failed: $(cat "$dir/shard-$i.err")"
  done
  # Each job exactly once over the shards, each succeeded, each shard's report names itself.
  for ((i = 0; i < shards; ++i)); do
    [ "$(jq -c '[.shard.index, .shard.count]' "$dir/shard-$i.json")" = "[$i,$shards]" ] ||
      fail "$name: shard $i reports $(jq -c '.shard' "$dir/shard-$i.json")"
  done
  local done_jobs
  done_jobs=$(jq -s -c '[.[].jobs[] | select(.ok) | .index] | sort' "$dir"/shard-*.json)
  [ "$done_jobs" = "$(jq -c '[range(0; .jobs | length)]' "$out/manifest.json")" ] ||
    fail "$name: jobs exported (sorted, with repeats): $done_jobs; expected each of 0..$((job_count - 1)) once"
  [ "$(jq -s '[.[].failed] | add' "$dir"/shard-*.json)" = 0 ] || fail "$name: a job failed"
  # The same bytes as the single run, file for file.
  diff -r "$out/single/out" "$dir/out" > "$dir/diff.txt" || fail "$name: outputs differ from the single run: $(cat "$dir/diff.txt")"
  say "$name: $shards shards, $job_count jobs each exported once, outputs identical ($(ls "$dir/out" | wc -l) files)"
}

# Kubernetes: the container's command (one flow-style list, valid JSON) and completions.
yaml=$source/installer/farm/kubernetes-indexed-job.yaml
completions=$(sed -nE 's/^  completions: *([0-9]+).*/\1/p' "$yaml")
command_json=$(sed -nE 's/^ *command: *(\[.*\]) *$/\1/p' "$yaml")
[ -n "$completions" ] && [ -n "$command_json" ] || fail "$yaml: no completions or command"
grep -qE '^  completionMode: Indexed' "$yaml" || fail "$yaml: not an Indexed Job"
mapfile -t k8s_words < <(jq -r '.[]' <<< "$command_json")
[ "${k8s_words[0]}" = motionlod ] && [ "${k8s_words[2]}" = /data/manifest.json ] ||
  fail "$yaml: the command is not motionlod batch /data/manifest.json …: ${k8s_words[*]}"
grep -qF -- "\$(JOB_COMPLETION_INDEX)/$completions" <<< "$command_json" ||
  fail "$yaml: --shard is not \$(JOB_COMPLETION_INDEX)/$completions (completions)"
k8s_words[0]=@MOTIONLOD@
k8s_words[2]=@MANIFEST@
k8s_words=("${k8s_words[@]//\$(JOB_COMPLETION_INDEX)/@INDEX@}")
run_shards kubernetes "$completions" "${k8s_words[@]}"

# HTCondor: executable, arguments (one quoted string, new syntax) and queue $(SHARDS).
sub=$source/installer/farm/motionlod.sub
shards=$(sed -nE 's/^SHARDS *= *([0-9]+).*/\1/p' "$sub")
executable=$(sed -nE 's/^executable *= *(.*[^ ]) *$/\1/p' "$sub")
arguments=$(sed -nE 's/^arguments *= *"(.*)" *$/\1/p' "$sub")
[ -n "$shards" ] && [ -n "$executable" ] && [ -n "$arguments" ] || fail "$sub: no SHARDS, executable or arguments"
grep -qE '^queue \$\(SHARDS\) *$' "$sub" || fail "$sub: does not queue \$(SHARDS) processes"
[ "${executable##*/}" = motionlod ] || fail "$sub: the executable is $executable"
arguments=${arguments//\$(SHARDS)/$shards}
arguments=${arguments//\$(Process)/@INDEX@}
arguments=${arguments//\/data\/manifest.json/@MANIFEST@}
read -r -a condor_words <<< "$arguments"
[ "${condor_words[0]}" = batch ] || fail "$sub: arguments do not start with batch"
run_shards htcondor "$shards" @MOTIONLOD@ "${condor_words[@]}"
say "ok"
