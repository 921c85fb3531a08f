#!/usr/bin/env bash
# The real-GPU-compiler check of .ci/run (not of `make test`): the compilers
# made by tools/cross/make_gpu_compilers.sh, then `parallax profile --gpu`
# on a few variants with two of them (Mali-G57's Valhall compiler and
# Adreno 630's ir3), and every variant must come back with the compiler's
# own figures: fragment instructions from both, cycles and a bound pipe from
# Valhall. Exit 1 naming what is missing.
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
PY
