#!/usr/bin/env python3
"""A QA campaign of faults around real exports (issue 29): signals, concurrent writers, full disks.

The mutant campaign (scripts/qa-campaign.py) feeds bad input; this one feeds bad luck to good
input, and checks the promise that an output is always entirely old or entirely new:

  signals      an export is sent SIGINT or SIGTERM at a random moment of its run (its length
               measured first); it must end within --signal-limit seconds of the signal, and
               leave the old output byte for byte or a complete new one that reads back, and
               no temporary file.
  concurrency  --writers exports of different clips to one bundle at once, --rounds times; at
               the end of each round the bundle and its manifest must be one export's (`info`
               does not warn that the manifest does not belong to the bundle).
  disk-full    an export into a small tmpfs (sizes from nearly empty to nearly enough) that
               holds the previous output; it must fail with an error line, leave the old
               output byte for byte and no temporary file, or succeed with a valid output.

Every run is a line of runs.jsonl in the work folder; the table is printed at the end and
written to summary.md. Needs root for the tmpfs mounts of disk-full (skipped otherwise).

  scripts/qa-faults.py --motionlod build/bin/motionlod --signals 136 --rounds 100 \\
      --disk-full 96 --work /tmp/mlod-qa-faults
"""

import argparse
import hashlib
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

MODELS = Path("/usr/share/assimp/models")
ROOT = Path(__file__).resolve().parent.parent
SAMPLE = ROOT / "resources" / "sample" / "cmu_01_01_excerpt.bvh"
# (input, plugin, output name): real files the project ships or Debian's assimp-testmodels holds
EXPORTS = [
    (SAMPLE, "bundle", "out.mlodb"),
    (MODELS / "BVH" / "01_03.bvh", "bundle", "out.mlodb"),
    (MODELS / "X" / "BCN_Epileptic.X", "gltf", "out.glb"),
    (MODELS / "BVH" / "Boxing_Toes.bvh", "gltf", "out.gltf"),
]
CLIPS = [SAMPLE, MODELS / "BVH" / "01_01.bvh", MODELS / "BVH" / "01_03.bvh", MODELS / "BVH" / "Boxing_Toes.bvh"]


def digest(path: Path) -> str | None:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None


def outputs_of(out: Path) -> list[Path]:
    """The files an export to `out` writes: a bundle and its manifest; a glTF (buffers embedded)."""
    if out.suffix == ".mlodb":
        return [out, out.with_name(out.name + ".json")]
    return [out]


def snapshot(out: Path) -> dict[str, str | None]:
    return {p.name: digest(p) for p in outputs_of(out)}


def reads_back(motionlod: str, out: Path) -> tuple[bool, str]:
    if out.suffix == ".glb":
        head = out.read_bytes()[:12] if out.is_file() else b""
        ok = len(head) == 12 and head[:4] == b"glTF" and struct.unpack("<I", head[8:12])[0] == out.stat().st_size
        return ok, "" if ok else "not a whole GLB"
    run = subprocess.run([motionlod, "info", str(out)], capture_output=True, timeout=120)
    err = run.stderr.decode("utf-8", "replace")
    if run.returncode != 0:
        return False, "info failed: " + err[-200:]
    if "does not belong" in err:
        return False, "mixed: " + err.strip().splitlines()[-1][:200]
    return True, ""


def strays(folder: Path, out: Path) -> list[str]:
    keep = {p.name for p in outputs_of(out)}
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


def export_argv(motionlod: str, source: Path, plugin: str, out: Path) -> list[str]:
    return [motionlod, "export", str(source), "--plugin", plugin, "-o", str(out), "--quiet"]


def signals_phase(args, motionlod: str, work: Path, rng: random.Random, log) -> dict[str, int]:
    counts: dict[str, int] = {}
    durations: dict[str, float] = {}
    for index in range(args.signals):
        source, plugin, name = EXPORTS[index % len(EXPORTS)]
        folder = work / "signals"
        if folder.exists():
            shutil.rmtree(folder)
        folder.mkdir(parents=True)
        out = folder / name
        if str(source) not in durations:  # how long a whole export takes
            scratch = work / "signals-probe"
            shutil.rmtree(scratch, ignore_errors=True)
            scratch.mkdir(parents=True)
            start = time.monotonic()
            subprocess.run(export_argv(motionlod, source, plugin, scratch / name), capture_output=True, check=True)
            durations[str(source)] = time.monotonic() - start
        # the old output: another clip's (an export is deterministic: the same input would
        # write the same bytes, and old could not be told from new)
        other = SAMPLE if source != SAMPLE else CLIPS[-1]
        first = subprocess.run(export_argv(motionlod, other, plugin, out), capture_output=True)
        if first.returncode != 0:
            raise SystemExit(f"the export to prepare an old output failed: {first.stderr.decode()[-300:]}")
        old = snapshot(out)
        sig = rng.choice([signal.SIGINT, signal.SIGTERM])
        delay = rng.uniform(0.0, durations[str(source)] * 1.1)
        process = subprocess.Popen(export_argv(motionlod, source, plugin, out), stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, start_new_session=True)
        time.sleep(delay)
        sent = time.monotonic()
        process.send_signal(sig)
        try:
            _, stderr = process.communicate(timeout=args.timeout)
            answered = time.monotonic() - sent
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            _, stderr = process.communicate()
            answered = None
        now = snapshot(out)
        detail = ""
        if answered is None:
            verdict, detail = "hang", f"still running {args.timeout:.0f} s after {sig.name}"
        elif strays(folder, out):
            verdict, detail = "stray", ",".join(strays(folder, out))
        elif now == old:
            verdict = "old"
        elif None in now.values():
            verdict, detail = "lost", json.dumps(now)
        else:
            ok, why = reads_back(motionlod, out)
            verdict, detail = ("new", "") if ok else ("broken", why)
        if answered is not None and answered > args.signal_limit and verdict in ("old", "new"):
            verdict, detail = "slow", f"{answered:.2f} s after {sig.name}"
        counts[verdict] = counts.get(verdict, 0) + 1
        record = {"phase": "signals", "run": index, "source": str(source), "plugin": plugin, "signal": sig.name,
                  "delay": round(delay, 3), "answered": None if answered is None else round(answered, 3),
                  "exit": process.returncode, "verdict": verdict, "detail": detail,
                  "stderr": stderr.decode("utf-8", "replace")[-160:]}
        log.write(json.dumps(record) + "\n")
        log.flush()
        if verdict not in ("old", "new"):
            print(f"signals {index}: {verdict}: {detail}", flush=True)
    return counts


def concurrency_phase(args, motionlod: str, work: Path, rng: random.Random, log) -> dict[str, int]:
    counts: dict[str, int] = {}
    folder = work / "concurrency"
    for round_ in range(args.rounds):
        if folder.exists():
            shutil.rmtree(folder)
        folder.mkdir(parents=True)
        out = folder / "out.mlodb"
        clips = CLIPS[: args.writers]
        rng.shuffle(clips)
        processes = [subprocess.Popen(export_argv(motionlod, clip, "bundle", out), stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE) for clip in clips]
        codes = []
        for process in processes:
            try:
                process.communicate(timeout=args.timeout)
            except subprocess.TimeoutExpired:
                process.kill()
                process.communicate()
            codes.append(process.returncode)
        if any(code is None or code < 0 for code in codes):
            verdict, detail = "hang", json.dumps(codes)
        elif not any(code == 0 for code in codes):
            verdict, detail = "none-landed", json.dumps(codes)
        elif strays(folder, out):
            verdict, detail = "stray", ",".join(strays(folder, out))
        else:
            ok, why = reads_back(motionlod, out)
            verdict, detail = ("whole", "") if ok else ("mixed", why)
        counts[verdict] = counts.get(verdict, 0) + 1
        record = {"phase": "concurrency", "round": round_, "clips": [str(c) for c in clips], "exits": codes,
                  "verdict": verdict, "detail": detail}
        log.write(json.dumps(record) + "\n")
        log.flush()
        if verdict != "whole":
            print(f"concurrency {round_}: {verdict}: {detail}", flush=True)
    return counts


def disk_full_phase(args, motionlod: str, work: Path, rng: random.Random, log) -> dict[str, int]:
    counts: dict[str, int] = {}
    if os.geteuid() != 0:
        print("disk-full: skipped (tmpfs mounts need root)", flush=True)
        return counts
    mount = work / "disk"
    mount.mkdir(parents=True, exist_ok=True)
    sizes: dict[str, int] = {}
    for index in range(args.disk_full):
        source, plugin, name = EXPORTS[index % len(EXPORTS)]
        key = str(source) + plugin
        if key not in sizes:  # what one output takes, measured on a roomy folder
            probe = work / "disk-probe"
            shutil.rmtree(probe, ignore_errors=True)
            probe.mkdir(parents=True)
            subprocess.run(export_argv(motionlod, source, plugin, probe / name), capture_output=True, check=True)
            sizes[key] = sum(p.stat().st_size for p in probe.iterdir())
        need = sizes[key]
        # room for the old output and a share of a second one: from none of it to a little more
        # than all (the same input: the old output is the new one's bytes, so a failed export
        # that replaced it would go unseen; "lost" is an old output gone or cut)
        size_kb = (need + int(need * rng.uniform(0.0, 1.05))) // 1024 + 8
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size_kb}k", "tmpfs", str(mount)], check=True)
        try:
            out = mount / name
            prepared = subprocess.run(export_argv(motionlod, source, plugin, out), capture_output=True)
            if prepared.returncode != 0:  # the tmpfs cannot even hold one: start from no old output
                for p in mount.iterdir():
                    p.unlink()
            old = snapshot(out)
            run = subprocess.run(export_argv(motionlod, source, plugin, out), capture_output=True, timeout=args.timeout)
            err = run.stderr.decode("utf-8", "replace")
            now = snapshot(out)
            detail = ""
            if strays(mount, out):
                verdict, detail = "stray", ",".join(strays(mount, out))
            elif run.returncode == 0:
                ok, why = reads_back(motionlod, out)
                verdict, detail = ("new", "") if ok else ("broken", why)
            elif not any(line.startswith("error: ") for line in err.splitlines()):
                verdict, detail = "silent", f"exit {run.returncode}: {err[-200:]}"
            elif now != old:
                verdict, detail = "lost", json.dumps({"old": old, "now": now})
            else:
                verdict = "old"
        finally:
            subprocess.run(["umount", str(mount)], check=False)
        counts[verdict] = counts.get(verdict, 0) + 1
        record = {"phase": "disk-full", "run": index, "source": str(source), "plugin": plugin, "tmpfs_kb": size_kb,
                  "needed": need, "exit": run.returncode, "verdict": verdict, "detail": detail}
        log.write(json.dumps(record) + "\n")
        log.flush()
        if verdict not in ("old", "new"):
            print(f"disk-full {index}: {verdict}: {detail}", flush=True)
    return counts


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionlod", default="build/bin/motionlod")
    parser.add_argument("--signals", type=int, default=40, help="exports interrupted by a signal")
    parser.add_argument("--signal-limit", type=float, default=1.0, help="seconds an export may take to stop")
    parser.add_argument("--rounds", type=int, default=20, help="rounds of concurrent exports to one bundle")
    parser.add_argument("--writers", type=int, default=4, help="concurrent exports per round (at most 4)")
    parser.add_argument("--disk-full", type=int, default=24, help="exports into a small tmpfs")
    parser.add_argument("--seed", type=int, default=29)
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds before a run counts as a hang")
    parser.add_argument("--work", default="/tmp/mlod-qa-faults")
    args = parser.parse_args()
    motionlod = str(Path(args.motionlod).resolve())
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    missing = [str(p) for p, _, _ in EXPORTS if not p.is_file()] + [str(p) for p in CLIPS if not p.is_file()]
    if missing:
        print("missing input files: " + ", ".join(sorted(set(missing))), file=sys.stderr)
        return 1
    rng = random.Random(args.seed)
    with open(work / "runs.jsonl", "a") as log:
        phases = {"signals": signals_phase(args, motionlod, work, rng, log),
                  "concurrency": concurrency_phase(args, motionlod, work, rng, log),
                  "disk-full": disk_full_phase(args, motionlod, work, rng, log)}
    good = {"signals": ("old", "new"), "concurrency": ("whole",), "disk-full": ("old", "new")}
    lines = ["| phase | runs | good | verdicts |", "|---|---|---|---|"]
    failed = False
    for phase, counts in phases.items():
        runs = sum(counts.values())
        fine = sum(counts.get(v, 0) for v in good[phase])
        failed = failed or fine != runs
        lines.append(f"| {phase} | {runs} | {fine} | " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())) + " |")
    summary = "\n".join(lines)
    (work / "summary.md").write_text(summary + "\n")
    print(summary)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
