#!/usr/bin/env python3
"""A QA campaign on mutated real files (issue 29): nothing crashes, nothing hangs.

Mutates real files of several formats from Debian's assimp-testmodels (bit flips, byte runs
deleted or duplicated, truncation; seeded, so the same arguments give the same mutants),
runs five commands on each mutant with a timeout, and classifies every run:

  ok       exit 0 with a valid output (JSON on stdout; an export's file readable back)
  refused  exit 2 with an `error: FILE: reason` line naming the mutant, nothing written
  crash    ended by a signal
  hang     still running at the timeout (killed)
  other    anything else (exit 1, exit 2 without the error line, an invalid output, a
           partial file left behind ...)

Every run is one line of runs.jsonl in the work folder; the mutants of crash, hang and
other runs are kept under keep/ with the command that failed; the table is printed at the
end (and written to summary.md). Run it at low priority beside other work:

  nice -n 19 scripts/qa-campaign.py --motionlod build/bin/motionlod --mutants 300 \\
      --work /tmp/qa

Round 3's campaign is --mutants 3000 (x 5 commands); --jobs 2 halves its hours on an idle
2-core machine. Its faults (signals, concurrent writers, full disks) are scripts/qa-faults.py.
"""

import argparse
import concurrent.futures
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

MODELS = Path("/usr/share/assimp/models")
# Real files of several formats under MODELS, each whole in one file (no side files).
SOURCES = [
    "BVH/01_01.bvh",
    "X/BCN_Epileptic.X",
    "Collada/cube_tristrips.dae",
    "Collada/box_nested_animation.dae",
    "glTF2/simple_skin/simple_skin.gltf",
    "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
    "3DS/RotatingCube.3DS",
    "FBX/box.fbx",
    "OBJ/spider.obj",
    "X/test.x",
    "MD5/SimpleCube.md5mesh",
    "SMD/triangle.smd",
]

COMMANDS = {
    "info": lambda f, out: ["info", f, "--json"],
    "simplify": lambda f, out: ["simplify", f, "--threshold", "5,50", "--json"],
    "export-bundle": lambda f, out: ["export", f, "--plugin", "bundle", "-o", str(out / "out.mlodb"), "--quiet"],
    "export-gltf": lambda f, out: ["export", f, "--plugin", "gltf", "-o", str(out / "out.glb"), "--quiet"],
    "meshlod": lambda f, out: ["meshlod", f, "--ratio", "0.5", "--json"],
}


def mutate(data: bytes, rng: random.Random) -> tuple[bytes, str]:
    """One seeded mutation of `data` and its description."""
    data = bytearray(data)
    kind = rng.choice(["flip", "flip", "delete", "duplicate", "truncate"])
    n = len(data)
    if n == 0:
        return bytes(data), "empty"
    if kind == "flip":
        count = rng.randint(1, 8)
        where = []
        for _ in range(count):
            i = rng.randrange(n)
            bit = rng.randrange(8)
            data[i] ^= 1 << bit
            where.append(f"{i}.{bit}")
        return bytes(data), "flip " + ",".join(where)
    if kind == "truncate":
        at = rng.randrange(n)
        return bytes(data[:at]), f"truncate {at}"
    length = min(n, max(1, int(rng.expovariate(1 / 64))))
    at = rng.randrange(n - length + 1)
    if kind == "delete":
        del data[at:at + length]
        return bytes(data), f"delete {at}+{length}"
    data[at:at] = data[at:at + length]
    return bytes(data), f"duplicate {at}+{length}"


def valid_glb(path: Path) -> bool:
    with open(path, "rb") as f:
        head = f.read(12)
    if len(head) < 12 or head[:4] != b"glTF":
        return False
    return struct.unpack("<I", head[8:12])[0] == path.stat().st_size


def classify(command: str, mutant: Path, out: Path, run, timed_out: bool, motionlod: str, timeout: float):
    if timed_out:
        return "hang", "timeout"
    code = run.returncode
    if code < 0:
        return "crash", f"signal {-code}"
    if code >= 128 and code - 128 in (signal.SIGSEGV, signal.SIGABRT, signal.SIGBUS, signal.SIGFPE, signal.SIGILL):
        return "crash", f"exit {code}"
    written = sorted(p.name for p in out.iterdir())
    err = run.stderr.decode("utf-8", "replace")
    if code == 2:
        if not any(line.startswith(f"error: {mutant}: ") for line in err.splitlines()):
            return "other", "exit 2 without an error line naming the file: " + err[-200:]
        if written:
            return "other", "exit 2 left files: " + ",".join(written)
        return "refused", err.strip().splitlines()[-1][len(f"error: {mutant}: "):][:160]
    if code != 0:
        return "other", f"exit {code}: " + err[-200:]
    if command.startswith("export"):
        expected = "out.mlodb" if command == "export-bundle" else "out.glb"
        if expected not in written:
            return "other", "exit 0 without the output file"
        if command == "export-gltf" and not valid_glb(out / expected):
            return "other", "exit 0 with an invalid GLB"
        if command == "export-bundle":
            try:
                check = subprocess.run([motionlod, "info", str(out / expected)], capture_output=True,
                                       timeout=timeout)
            except subprocess.TimeoutExpired:  # recorded, not fatal: the campaign goes on
                return "hang", f"info on the exported bundle did not answer within {timeout:.0f} s"
            if check.returncode != 0:
                return "other", "exit 0 but the bundle does not read back: " + check.stderr.decode()[-200:]
        return "ok", ""
    try:
        json.loads(run.stdout)
    except ValueError:
        return "other", "exit 0 without a JSON document"
    return "ok", ""


def run_one(motionlod: str, command: str, mutant: Path, out: Path, timeout: float):
    if out.exists():
        shutil.rmtree(out)
    out.mkdir(parents=True)
    argv = [motionlod] + COMMANDS[command](str(mutant), out)
    start = time.monotonic()
    process = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True)
    timed_out = False
    try:
        stdout, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        os.killpg(process.pid, signal.SIGKILL)
        stdout, stderr = process.communicate()
    seconds = time.monotonic() - start
    run = subprocess.CompletedProcess(argv, process.returncode, stdout, stderr)
    verdict, detail = classify(command, mutant, out, run, timed_out, motionlod, timeout)
    return verdict, detail, seconds


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionlod", default="build/bin/motionlod")
    parser.add_argument("--mutants", type=int, default=300, help="mutants in all, spread over the sources")
    parser.add_argument("--seed", type=int, default=29)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per run")
    parser.add_argument("--work", default="/tmp/mlod-qa-campaign")
    parser.add_argument("--commands", default=",".join(COMMANDS), help="comma-separated subset of " + ",".join(COMMANDS))
    parser.add_argument("--jobs", type=int, default=1, help="mutants run side by side (their runs' times then share the cores)")
    args = parser.parse_args()
    motionlod = str(Path(args.motionlod).resolve())
    commands = args.commands.split(",")
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    sources = [MODELS / path for path in SOURCES if (MODELS / path).is_file()]
    if not sources:
        print(f"no source files under {MODELS}", file=sys.stderr)
        return 1
    log = open(work / "runs.jsonl", "a")
    counts: dict[tuple[str, str], int] = {}
    by_format: dict[tuple[str, str], int] = {}
    lock = threading.Lock()

    def one_mutant(index: int) -> None:
        source = sources[index % len(sources)]
        rng = random.Random(f"{args.seed}/{index}")  # each mutant on its own: a rerun of one is the same
        data, how = mutate(source.read_bytes(), rng)
        folder = work / "mutants" / f"{index:05d}"
        if folder.exists():
            shutil.rmtree(folder)
        folder.mkdir(parents=True)
        mutant = folder / source.name
        mutant.write_bytes(data)
        for command in commands:
            verdict, detail, seconds = run_one(motionlod, command, mutant, work / "out" / f"{index:05d}", args.timeout)
            record = {"mutant": index, "source": str(source.relative_to(MODELS)), "mutation": how,
                      "command": command, "verdict": verdict, "detail": detail, "seconds": round(seconds, 3)}
            with lock:
                counts[(command, verdict)] = counts.get((command, verdict), 0) + 1
                suffix = source.suffix.lower()
                by_format[(suffix, verdict)] = by_format.get((suffix, verdict), 0) + 1
                log.write(json.dumps(record) + "\n")
                log.flush()
            if verdict in ("crash", "hang", "other"):
                keep = work / "keep" / f"{index:05d}-{command}"
                keep.mkdir(parents=True, exist_ok=True)
                shutil.copy(mutant, keep / mutant.name)
                (keep / "run.json").write_text(json.dumps(record, indent=1))
                print(f"{verdict}: {index} {command} {source.name} ({how}): {detail}", flush=True)
        shutil.rmtree(folder)
        shutil.rmtree(work / "out" / f"{index:05d}", ignore_errors=True)

    # (each mutant and its outputs in folders of their own: --jobs runs them side by side)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for future in [pool.submit(one_mutant, index) for index in range(args.mutants)]:
            future.result()
    verdicts = ["ok", "refused", "crash", "hang", "other"]
    lines = ["| command | " + " | ".join(verdicts) + " |", "|---|" + "---|" * len(verdicts)]
    for command in commands:
        lines.append(f"| {command} | " + " | ".join(str(counts.get((command, v), 0)) for v in verdicts) + " |")
    lines.append("| **all** | " + " | ".join(str(sum(counts.get((c, v), 0) for c in commands)) for v in verdicts) + " |")
    lines += ["", "| format | " + " | ".join(verdicts) + " |", "|---|" + "---|" * len(verdicts)]
    for suffix in sorted({s for s, _ in by_format}):
        lines.append(f"| {suffix} | " + " | ".join(str(by_format.get((suffix, v), 0)) for v in verdicts) + " |")
    summary = "\n".join(lines)
    (work / "summary.md").write_text(summary + "\n")
    print(summary)
    return 0


if __name__ == "__main__":
    sys.exit(main())
