#!/usr/bin/env bash
# SIGINT and SIGTERM leave nothing behind (core/interrupts.h): `parallax
# profile` interrupted while a vendor compiler runs kills the compiler and
# the child it started (they lead their own process group, so the signal
# does not reach them by itself) and removes its parallax-vendor-* folder;
# `parallax render --textures` interrupted while it converts removes its
# parallax-textures-* folder. Either way parallax dies of the signal (a
# shell sees 128 + its number). Waits are bounded polls, only hang guards.
# Usage: interrupts.sh PARALLAX_BINARY
set -uo pipefail
parallax=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# Polls (every 20 ms, up to 20 s) until the command succeeds.
wait_for() {
    local i
    for ((i = 0; i < 1000; ++i)); do
        "$@" && return 0
        sleep 0.02
    done
    return 1
}
# A process still running: /proc has it and it is not a zombie (one whose
# parent died may wait a while for init to reap it).
alive() { [ -r "/proc/$1/stat" ] && [ "$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null)" != Z ]; }
dead() { ! alive "$1"; }
leftovers() { find "$1" -mindepth 1 -maxdepth 1 -name "$2" | head -3; }
# Whether FOLDER holds something named PATTERN (a function, so that
# wait_for looks again on each poll).
has_leftovers() { [ -n "$(leftovers "$1" "$2")" ]; }

# A malioc that never finishes: it records its pid and its child's, then
# says it has started.
mkdir -p "$work/bin"
cat >"$work/bin/malioc" <<'SH'
#!/bin/sh
echo $$ >"$STATE/compiler.pid"
sleep 1000 &
echo $! >"$STATE/grandchild.pid"
touch "$STATE/started"
wait
SH
chmod +x "$work/bin/malioc"

# profile_case SIGNAL STATUS
profile_case() {
    local signal=$1 expected=$2 state="$work/profile_$1" status
    mkdir -p "$state/tmp"
    # A background job of a script starts with SIGINT ignored, and parallax
    # leaves an inherited "ignore" alone: env gives it the default back.
    STATE=$state TMPDIR=$state/tmp PATH="$work/bin:$PATH" env --default-signal=INT,TERM \
        "$parallax" profile --no-time --no-nir --variants 'normal es3' >"$state/out" 2>&1 &
    local pid=$!
    if ! wait_for test -e "$state/started"; then
        fail "profile ($signal): the fake compiler never started: $(cat "$state/out")"
        kill -KILL "$pid" 2>/dev/null
        return
    fi
    kill "-$signal" "$pid"
    wait "$pid"
    status=$?
    [ "$status" = "$expected" ] || fail "profile: SIG$signal gave exit status $status, expected $expected: $(cat "$state/out")"
    local compiler grandchild
    compiler=$(cat "$state/compiler.pid") grandchild=$(cat "$state/grandchild.pid")
    wait_for dead "$compiler" || fail "profile: SIG$signal left the vendor compiler (pid $compiler) running"
    wait_for dead "$grandchild" || fail "profile: SIG$signal left the compiler's child (pid $grandchild) running"
    kill -KILL "$compiler" "$grandchild" 2>/dev/null
    local left
    left=$(leftovers "$state/tmp" 'parallax-vendor-*')
    [ -z "$left" ] || fail "profile: SIG$signal left $left"
    [ "$status" = "$expected" ] && dead "$compiler" && dead "$grandchild" && [ -z "$left" ] &&
        echo "ok: SIG$signal during a vendor compiler run: exit $status, compiler and its child gone, no folder left"
}
profile_case INT 130
profile_case TERM 143

# render --textures: a scene whose textures take seconds to convert (ETC2
# at 2048x2048); interrupted as soon as the conversion's folder appears.
state="$work/render"
mkdir -p "$state/tmp" "$state/cache"
cat >"$state/big.json" <<'JSON'
{"name": "big", "materials": [{"name": "m", "height": {"procedural": "bricks", "size": 2048}, "height_scale": 0.06,
 "albedo": {"procedural": "bricks", "size": 2048}}],
 "objects": [{"name": "floor", "mesh": {"type": "plane"}, "material": "m"}]}
JSON
TMPDIR=$state/tmp XDG_CACHE_HOME=$state/cache env --default-signal=INT,TERM \
    "$parallax" render "$state/big.json" --textures etc2 --size 16x16 -o "$state/out.png" >"$state/out" 2>&1 &
pid=$!
if wait_for has_leftovers "$state/tmp" 'parallax-textures-*'; then
    kill -INT "$pid"
    wait "$pid"
    status=$?
    left=$(leftovers "$state/tmp" 'parallax-textures-*')
    if [ "$status" = 130 ] && [ -z "$left" ]; then
        echo "ok: SIGINT during render --textures: exit 130, no folder left"
    else
        fail "render --textures: SIGINT gave exit status $status (expected 130), left '${left}': $(tail -3 "$state/out")"
    fi
else
    fail "render --textures never made its folder: $(tail -3 "$state/out")"
    kill -KILL "$pid" 2>/dev/null
fi

[ "$failures" = 0 ] && echo "all interrupt cases leave nothing behind" || { echo "$failures interrupt case(s) failed"; exit 1; }
