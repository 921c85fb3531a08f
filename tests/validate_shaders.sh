#!/usr/bin/env bash
# Every shader variant the program can build must pass glslangValidator: as
# GLSL ES 1.00 under the ES 2.0 minimum limits and the Appendix A loop and
# indexing restrictions (tests/glsl_es100_strict.conf), and as GLSL ES 3.00.
# Usage: validate_shaders.sh PARALLAX_BINARY TESTS_DIR
set -euo pipefail
parallax=$1
tests_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
strict="$tests_dir/glsl_es100_strict.conf"

command -v glslangValidator >/dev/null || { echo "glslangValidator not found: apt-get install glslang-tools"; exit 1; }

# The config must really enforce Appendix A: a non-constant loop bound passes
# glslang's default limits and fails the strict ones.
violation="$tests_dir/shaders/appendix_a_violation.frag"
glslangValidator "$violation" >/dev/null || { echo "FAIL: default limits rejected the negative control"; exit 1; }
if glslangValidator "$strict" "$violation" >/dev/null 2>&1; then
    echo "FAIL: $strict accepted a non-constant loop bound (Appendix A not enforced)"; exit 1
fi

failures=0
total=0
for es in 2 3; do
    "$parallax" shaders --es "$es" --out "$work/es$es" >/dev/null
    for f in "$work/es$es"/*; do
        total=$((total + 1))
        if [ "$es" = 2 ]; then
            head -1 "$f" | grep -qx '#version 100' || { echo "FAIL: $f does not start with #version 100"; failures=$((failures + 1)); continue; }
            out=$(glslangValidator "$strict" "$f" 2>&1) || { echo "FAIL (GLSL ES 1.00 strict): $(basename "$f")"; echo "$out" | head -20; failures=$((failures + 1)); }
        else
            head -1 "$f" | grep -qx '#version 300 es' || { echo "FAIL: $f does not start with #version 300 es"; failures=$((failures + 1)); continue; }
            out=$(glslangValidator "$f" 2>&1) || { echo "FAIL (GLSL ES 3.00): $(basename "$f")"; echo "$out" | head -20; failures=$((failures + 1)); }
        fi
    done
done
[ "$total" -gt 100 ] || { echo "FAIL: only $total shader files were written; expected every variant"; exit 1; }
echo "$((total - failures)) of $total shader files valid"
[ "$failures" = 0 ]
