#!/usr/bin/env python3
"""The studio part of a QA round (issue 29): mutated projects opened in the studio.

Writes a few real projects (Testwuson with CMU 01_01 mapped onto it, BCN_Epileptic with
01_03, both with budget levels, by `bench_studio_export --make-project`; the sample clip),
mutates them (JSON-aware: numbers pushed to extremes, values of the wrong type, keys
deleted, arrays repeated, names 100,000 characters long, asset paths outside the project's
folder or at devices and folders; byte-level: bit flips, truncation, bytes deleted), opens
each mutant with `motionlod-studio MUTANT --screenshot PNG` on the offscreen platform with a
timeout, and classifies every run:

  opened   exit 0, a picture saved
  refused  exit 2 with an `error:` line naming the project, or exit 0/2 whose log names
           what it could not import
  crash    ended by a signal
  hang     still running at the timeout (killed)
  other    anything else (exit 1 or 2 without a reason, no picture)

and in every case the mutant itself must be byte for byte what it was (opening a project
writes nothing to it): a changed mutant counts as "lost". Seeded: the same arguments give
the same mutants. One line per run in runs.jsonl under --work, the mutants of bad runs kept
under keep/, the table printed at the end.

  scripts/qa-studio.py --studio build/bin/motionlod-studio \\
      --bench build/bin/bench_studio_export --mutants 170 --work /tmp/qa-studio
"""

import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

MODELS = Path("/usr/share/assimp/models")
REPO = Path(__file__).resolve().parent.parent


def make_bases(bench, work):
    """The real projects the mutants start from."""
    bases = []
    pairs = [("X/Testwuson.X", "BVH/01_01.bvh", "testwuson_0101.mlod"),
             ("X/BCN_Epileptic.X", "BVH/01_03.bvh", "bcn_0103.mlod")]
    for character, motion, name in pairs:
        out = work / "bases" / name
        out.parent.mkdir(parents=True, exist_ok=True)
        env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
        subprocess.run([bench, "--make-project", str(MODELS / character), str(MODELS / motion), str(out)],
                       check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        bases.append(out)
    # the sample clip alone, with two levels and per-joint settings, written by hand as the
    # studio writes it (version and keys from a saved project above)
    template = json.loads(bases[0].read_text())
    sample = dict(template)
    sample["assets"] = [dict(template["assets"][0])]
    sample["assets"][0]["path"] = str(REPO / "resources/sample/cmu_01_01_excerpt.bvh")
    sample["assets"][0]["unit_scale"] = 5.6444
    sample["assets"][0].pop("lods", None)  # the project's own set
    sample["mappings"] = []
    out = work / "bases" / "sample.mlod"
    out.write_text(json.dumps(sample, indent=2))
    bases.append(out)
    return bases


def paths_in(value, prefix=()):
    """Every (path, leaf) of a JSON value, leaves and containers alike."""
    yield prefix, value
    if isinstance(value, dict):
        for key, child in value.items():
            yield from paths_in(child, prefix + (key,))
    elif isinstance(value, list):
        for index, child in enumerate(value):
            yield from paths_in(child, prefix + (index,))


def set_at(document, path, value):
    if not path:
        return value
    target = document
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value
    return document


MAX_MUTANT_BYTES = 8_000_000  # a project of 8 MB: eight times the 1 MB figure
EXTREME_NUMBERS = [0, -1, 1e308, -1e308, 1e-308, 2**63, -(2**63), 2**64, 4294967295, 1e38, 3.5, 1e9]
ODD_PATHS = ["../../../../../../etc/passwd", "/dev/zero", "/proc/self/mem", "/", ".", "", "missing.bvh",
             "/usr/share/assimp/models/BVH", "C:\\\\x.bvh", "a" * 5000]


def mutate_json(text, rng):
    document = json.loads(text)
    entries = list(paths_in(document))
    kind = rng.choice(["number", "type", "delete", "repeat", "long-name", "path", "several"])
    if kind == "several":
        for _ in range(rng.randint(2, 6)):
            text = mutate_json(json.dumps(document), rng)[0]
            if len(text) > MAX_MUTANT_BYTES:
                break
            document = json.loads(text)
        return json.dumps(document), kind
    if kind == "number":
        numbers = [(p, v) for p, v in entries if isinstance(v, (int, float)) and not isinstance(v, bool)]
        if numbers:
            path, _ = rng.choice(numbers)
            document = set_at(document, path, rng.choice(EXTREME_NUMBERS))
    elif kind == "type":
        path, _ = rng.choice(entries[1:])
        document = set_at(document, path, rng.choice([None, "text", [], {}, True, 7, [1, 2, 3], {"a": 1}]))
    elif kind == "delete":
        keyed = [(p, v) for p, v in entries if p and isinstance(p[-1], str)]
        if keyed:
            path, _ = rng.choice(keyed)
            parent = document
            for step in path[:-1]:
                parent = parent[step]
            del parent[path[-1]]
    elif kind == "repeat":
        arrays = [(p, v) for p, v in entries if isinstance(v, list) and v]
        if arrays:
            path, value = rng.choice(arrays)
            times = rng.choice([2, 50, 2000])
            # a mutant stays under MAX_MUTANT_BYTES (repeats of repeats grow without bound)
            times = max(2, min(times, MAX_MUTANT_BYTES // max(1, len(json.dumps(value)))))
            document = set_at(document, path, value * times)
    elif kind == "long-name":
        strings = [(p, v) for p, v in entries if isinstance(v, str)]
        if strings:
            path, _ = rng.choice(strings)
            document = set_at(document, path, "x" * 100_000)
    elif kind == "path":
        assets = document.get("assets") if isinstance(document, dict) else None
        if isinstance(assets, list) and assets and isinstance(assets[0], dict):
            rng.choice(assets)["path"] = rng.choice(ODD_PATHS)
    return json.dumps(document, indent=rng.choice([None, 2])), kind


def mutate_bytes(data, rng):
    data = bytearray(data)
    kind = rng.choice(["flip", "truncate", "delete"])
    if kind == "flip":
        for _ in range(rng.randint(1, 8)):
            i = rng.randrange(len(data))
            data[i] ^= 1 << rng.randrange(8)
    elif kind == "truncate":
        data = data[:rng.randrange(len(data))]
    else:
        start = rng.randrange(len(data))
        del data[start:start + rng.randint(1, 200)]
    return bytes(data), "bytes-" + kind


def run_one(studio, mutant, png, home, timeout):
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen", HOME=str(home), XDG_RUNTIME_DIR=str(home / "xdg"))
    (home / "xdg").mkdir(parents=True, exist_ok=True)
    os.chmod(home / "xdg", 0o700)
    before = mutant.read_bytes()
    start = time.monotonic()
    process = subprocess.Popen([studio, str(mutant), "--screenshot", str(png)], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, errors="replace", start_new_session=True)
    try:
        out, err = process.communicate(timeout=timeout)
        status = process.returncode
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        out, err = process.communicate()
        status = None
    seconds = time.monotonic() - start
    lost = mutant.read_bytes() != before
    text = out + err
    named = mutant.name in err or "could not be imported" in text or "cannot" in text.lower()
    if status is None:
        verdict = "hang"
    elif status < 0:
        verdict = "crash"
    elif status == 0 and png.exists():
        verdict = "opened"
    elif status == 2 and "error:" in err and named and png.exists():
        verdict = "refused"
    else:
        verdict = "other"
    if lost:
        verdict = "lost"
    return verdict, status, seconds, text[-2000:], next((l for l in err.splitlines() if "error:" in l), "")[:300]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--studio", default=str(REPO / "build/bin/motionlod-studio"))
    parser.add_argument("--bench", default=str(REPO / "build/bin/bench_studio_export"))
    parser.add_argument("--mutants", type=int, default=170)
    parser.add_argument("--seed", type=int, default=29)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--work", default="/tmp/qa-studio")
    args = parser.parse_args()

    work = Path(args.work)
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    bases = make_bases(args.bench, work)
    rng = random.Random(args.seed)
    counts = {}
    slowest = (0.0, "")
    with open(work / "runs.jsonl", "w") as log:
        for index in range(args.mutants):
            base = bases[index % len(bases)]
            folder = work / f"m{index:04d}"
            folder.mkdir()
            text = base.read_text()
            if rng.random() < 0.75:
                mutated, kind = mutate_json(text, rng)
                data = mutated.encode()
            else:
                data, kind = mutate_bytes(text.encode(), rng)
            mutant = folder / base.name
            mutant.write_bytes(data)
            verdict, status, seconds, tail, reason = run_one(args.studio, mutant, folder / "shot.png", folder / "home",
                                                     args.timeout)
            counts[verdict] = counts.get(verdict, 0) + 1
            if seconds > slowest[0]:
                slowest = (seconds, str(mutant))
            log.write(json.dumps({"mutant": str(mutant), "base": base.name, "kind": kind, "verdict": verdict,
                                  "status": status, "seconds": round(seconds, 2), "reason": reason}) + "\n")
            log.flush()
            if verdict in ("crash", "hang", "other", "lost"):
                keep = work / "keep" / f"m{index:04d}"
                keep.mkdir(parents=True)
                shutil.copy(mutant, keep / base.name)
                (keep / "output.txt").write_text(tail)
            else:
                shutil.rmtree(folder)
            print(f"{index + 1}/{args.mutants} {base.name} {kind}: {verdict} ({seconds:.1f} s)", flush=True)
    print("\n| verdict | runs |\n|---|---|")
    for verdict in ("opened", "refused", "crash", "hang", "other", "lost"):
        print(f"| {verdict} | {counts.get(verdict, 0)} |")
    print(f"\nslowest: {slowest[0]:.1f} s ({slowest[1]})")
    return 0 if all(counts.get(v, 0) == 0 for v in ("crash", "hang", "other", "lost")) else 1


if __name__ == "__main__":
    sys.exit(main())
