#!/usr/bin/env bash
# The real-GPU-compiler check of .ci/run (not of `make test`): the compilers
# made by tools/cross/make_gpu_compilers.sh, then `parallax profile --gpu`
# on a few variants with two of them (Mali-G57's Valhall compiler and
# Adreno 630's ir3), and every variant must come back with the compiler's
# own figures: fragment instructions from both, cycles and a bound pipe from
# Valhall, and a 16-bit share read from its instruction listing; and
# `profile --gpu-precision` must find 16-bit instructions as written and
# next to none with every value highp. Exit 1 naming what is missing.
#   tests/cross/gpu_compilers_check.sh PARALLAX
set -euo pipefail
parallax=${1:?usage: $0 PARALLAX}
root=$(cd "$(dirname "$0")/../.." && pwd)
bash "$root/tools/cross/make_gpu_compilers.sh" >/dev/null
out=$(mktemp)
trap 'rm -f "$out"' EXIT
"$parallax" profile --gpu mali-g57,adreno-630 --variants '* es3 samples<=32 exact-view packed' --no-time --no-nir --format json >"$out"
python3 - "$out" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
variants = report["variants"]
problems = []
if len(variants) < 2:
    problems.append("fewer than 2 variants selected")
for v in variants:
    gpus = {g["target"]: g for g in v.get("gpu", [])}
    for target in ("mali-g57", "adreno-630"):
        g = gpus.get(target)
        if g is None:
            problems.append(f"{v['variant']}: no {target} figures"); continue
        s = g["summary"]
        if g.get("error") or not s.get("fragment_instructions"):
            problems.append(f"{v['variant']} on {target}: {g.get('error') or 'no fragment instructions'}")
        if target == "mali-g57" and (not s.get("fragment_cycles") or not s.get("bound")):
            problems.append(f"{v['variant']} on {target}: no cycles or bound pipe")
if problems:
    print("FAIL: real GPU compilers:\n  " + "\n  ".join(problems)); sys.exit(1)
print(f"ok: {len(variants)} variants on Mali-G57 and Adreno 630, each with the compiler's own figures")
for line in report["context"].get("gpu", []): print("  " + line)
for v in variants:
    s = {g["target"]: g for g in v.get("gpu", [])}["mali-g57"]["summary"]
    if s.get("narrow_share") is None:
        print(f"FAIL: {v['variant']} on mali-g57: no 16-bit share from the instruction listing"); sys.exit(1)
PY
# Precision on the real compiler: with every value highp, next to no 16-bit
# instruction is left; as written (mediump where the shaders declare it),
# a good share is.
"$parallax" profile --gpu mali-g57 --gpu-precision --variants 'normal es3' >"$out"
python3 - "$out" <<'PY'
import re, sys
rows = [l for l in open(sys.argv[1]) if l.startswith("normal es3")]
if len(rows) != 1:
    print("FAIL: --gpu-precision printed no row for normal es3"); sys.exit(1)
shares = [int(x) for x in re.findall(r"(\d+) % \(", rows[0])]
if len(shares) != 2 or not (shares[0] >= 20 and shares[1] <= 5):
    print(f"FAIL: --gpu-precision: 16-bit shares {shares} (as written, all highp): expected >= 20 and <= 5:\n{rows[0]}"); sys.exit(1)
print(f"ok: normal es3 on Mali-G57: {shares[0]} % 16-bit as written, {shares[1]} % with every value highp")
PY
