#!/usr/bin/env python3
"""Fuzz test of the command line (issue 16): mutates the shipped pipelines (byte flips, type
changes, extreme numbers) with a fixed seed, runs `crackflow validate` on every mutant and
`crackflow run --fast` on a sample of those that validate, each under a timeout and a memory cap.

Asserts: no death by a signal, exit codes only 0, 1 or 2 (and 143 after our own SIGTERM at the
timeout), and after every run a report.json that is strict JSON in valid UTF-8.

usage: fuzz_pipelines.py CRACKFLOW PIPELINE_DIR WORK_DIR [--mutants N] [--runs K] [--seed S]
"""
import argparse
import json
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import time

EXTREMES = ["0", "-1", "1e308", "-1e308", "1e-308", "1e9", "-1e9", "2147483648", "9223372036854775807",
            "99999999999999999999", ".nan", ".inf", "-.inf", "1e400", "0.0000001"]
TYPE_SWAPS = ["abc", "''", "[]", "[1, 2]", "{}", "{a: 1}", "true", "null", "~", "[[1]]", "\"\\xff\"", "'\u00e9'"]
NUMBER = re.compile(rb"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?(?![\w.])")
SCALAR = re.compile(rb"(:\s*)([^\s{}\[\],#][^\n{}\[\],#]*)")

# Shipped pipelines whose --fast run takes a few seconds: the sample of runs is drawn from these.
QUICK = ["loop_demo.yaml", "cut_box.yaml", "box_regions.yaml", "default.yaml", "edge_crack_mode1.yaml",
         "cube_tension.yaml", "notched_bar.yaml"]


def mutate(text, rng):
    data = bytearray(text)
    for _ in range(rng.randint(1, 3)):
        kind = rng.choice(["flip", "flip", "number", "number", "type", "type", "delete", "duplicate"])
        if kind == "flip" and data:
            i = rng.randrange(len(data))
            data[i] = rng.choice([data[i] ^ (1 << rng.randrange(8)), rng.randrange(256)])
        elif kind == "number":
            spans = [m.span() for m in NUMBER.finditer(data)]
            if spans:
                a, b = rng.choice(spans)
                data[a:b] = rng.choice(EXTREMES).encode()
        elif kind == "type":
            spans = [m.span(2) for m in SCALAR.finditer(data)]
            if spans:
                a, b = rng.choice(spans)
                data[a:b] = rng.choice(TYPE_SWAPS).encode()
        elif kind == "delete" and data:
            a = rng.randrange(len(data))
            del data[a:a + rng.randint(1, 20)]
        elif kind == "duplicate":
            lines = bytes(data).split(b"\n")
            i = rng.randrange(len(lines))
            lines.insert(i, lines[i])
            data = bytearray(b"\n".join(lines))
    return bytes(data)


def limit_memory(cap_bytes):
    def apply():
        # cap 0: no address-space cap (an AddressSanitizer binary reserves terabytes of shadow
        # memory and cannot start under one; it still has crackflow's own memory checks).
        if cap_bytes > 0:
            resource.setrlimit(resource.RLIMIT_AS, (cap_bytes, cap_bytes))
        os.setsid()
    return apply


def strict_json(path):
    with open(path, "rb") as f:
        raw = f.read()
    text = raw.decode("utf-8")  # strict: invalid UTF-8 raises

    def no_constants(name):
        raise ValueError("non-JSON constant " + name)
    return json.loads(text, parse_constant=no_constants)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("crackflow")
    ap.add_argument("pipelines")
    ap.add_argument("work")
    ap.add_argument("--mutants", type=int, default=3000)
    ap.add_argument("--runs", type=int, default=14)
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--timeout", type=float, default=30)
    ap.add_argument("--memory-gb", type=float, default=3, help="address-space cap per run in GiB; 0: none")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    sources = sorted(f for f in os.listdir(args.pipelines) if f.endswith(".yaml"))
    originals = {f: open(os.path.join(args.pipelines, f), "rb").read() for f in sources}
    shutil.rmtree(args.work, ignore_errors=True)
    mdir = os.path.join(args.work, "mutants")
    os.makedirs(mdir)
    # The thesis cases use pipelines/lib/ (type: use, relative to the file): the mutants beside it.
    if os.path.isdir(os.path.join(args.pipelines, "lib")):
        shutil.copytree(os.path.join(args.pipelines, "lib"), os.path.join(mdir, "lib"))
    mutants = []
    for i in range(args.mutants):
        src = sources[i % len(sources)]
        path = os.path.join(mdir, "m%05d_%s" % (i, src))
        with open(path, "wb") as f:
            f.write(mutate(originals[src], rng))
        mutants.append((path, src))
    cap = int(args.memory_gb * (1 << 30))
    failures = []
    started = time.time()

    # validate: in batches (one process checks many files); a batch that dies is re-run file by file
    # to name the culprit.
    def validate(paths):
        try:
            p = subprocess.run([args.crackflow, "validate"] + paths, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               preexec_fn=limit_memory(cap), timeout=max(60, len(paths)))
        except subprocess.TimeoutExpired:
            return -1000, b"validate hung (timeout)"
        return p.returncode, p.stdout + p.stderr

    valid = []
    batch = 50
    for k in range(0, len(mutants), batch):
        chunk = mutants[k:k + batch]
        code, out = validate([p for p, _ in chunk])
        if code not in (0, 2):
            for p, _ in chunk:
                c, o = validate([p])
                if c not in (0, 2):
                    failures.append("validate %s: exit %d (%s)\n%s" % (p, c, "signal %d" % -c if c < 0 else "code",
                                                                         o.decode("utf-8", "replace")[-2000:]))
            continue
        text = out.decode("utf-8", "replace")
        for p, src in chunk:
            if (p + ": ok (") in text:
                valid.append((p, src))
    validated = time.time() - started
    print("validate: %d mutants of %d pipelines, %d valid, %.1f s" % (len(mutants), len(sources), len(valid), validated))

    # run --fast: a sample of the valid mutants of the quick pipelines, each under the memory cap; at
    # the timeout SIGTERM, which must end the run cleanly (exit 143, report written).
    quick = [m for m in valid if m[1] in QUICK]
    sample = rng.sample(quick, min(args.runs, len(quick)))
    data_dir = os.getcwd()
    for n, (path, src) in enumerate(sample):
        out = os.path.join(args.work, "run%02d" % n)
        t0 = time.time()
        proc = subprocess.Popen([args.crackflow, "run", path, "--fast", "--threads", "2", "--out", out],
                                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=limit_memory(cap),
                                cwd=data_dir)
        terminated = False
        try:
            _, err = proc.communicate(timeout=args.timeout)
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGTERM)
            terminated = True
            try:
                _, err = proc.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                _, err = proc.communicate()
                failures.append("run %s (from %s): did not stop within 10 s of SIGTERM" % (path, src))
                continue
        code = proc.returncode
        allowed = (143,) if terminated else (0, 1, 2)
        tail = err.decode("utf-8", "replace")[-1500:]
        print("run %-40s exit %4d  %.1f s%s" % (os.path.basename(path), code, time.time() - t0,
                                               " (SIGTERM at the timeout)" if terminated else ""))
        if code not in allowed:
            failures.append("run %s (from %s): exit %d%s\n%s" % (path, src, code,
                                                                " (signal %d)" % -code if code < 0 else "", tail))
            continue
        if code in (0, 1, 143):
            report = os.path.join(out, "report.json")
            try:
                strict_json(report)
            except Exception as e:  # noqa: BLE001 - any failure to read it is the finding
                failures.append("run %s (from %s): report.json is not valid: %s" % (path, src, e))
    print("fuzz: %d failures, %.1f s in all" % (len(failures), time.time() - started))
    for f in failures:
        print("FAIL", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
