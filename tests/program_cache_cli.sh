#!/usr/bin/env bash
# `parallax render --program-cache DIR`: the first run compiles and stores,
# the second loads every program from DIR, a corrupt entry is rebuilt (the
# render still succeeds and says so), a folder that cannot be written is a
# warning, and without the option the entries go to $XDG_CACHE_HOME (never to
# the real $HOME here: both point into a temporary folder).
# Usage: program_cache_cli.sh PARALLAX_BINARY
set -uo pipefail
parallax=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export XDG_CACHE_HOME="$work/xdg" HOME="$work/home"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# run NAME ARGS...: renders default at 64x64; stdout in $work/NAME.out, stderr in $work/NAME.err.
run() {
    local name=$1
    shift
    if ! "$parallax" render default --size 64x64 --frames 1 -o "$work/$name.png" "$@" >"$work/$name.out" 2>"$work/$name.err"; then
        fail "$name: exit status $?: $(cat "$work/$name.err")"
        return 1
    fi
    [ -s "$work/$name.png" ] || fail "$name: no image"
    grep '^programs' "$work/$name.out"
}

# The "programs" line is "programs   N compiled, M from the binary cache (DIR), K stale entries rebuilt".
field() { sed -n "s/^programs *\([0-9]*\) compiled, \([0-9]*\) from the binary cache (.*), \([0-9]*\) stale.*/\\$2/p" "$work/$1.out"; }

for es in 3 2; do
    cache="$work/cache_es$es"
    run first$es --es $es --program-cache "$cache" || continue
    compiled=$(field first$es 1)
    [ "${compiled:-0}" -ge 1 ] && [ "$(field first$es 2)" = 0 ] || fail "es$es first run: $(grep '^programs' "$work/first$es.out")"
    grep -qF "($cache)" "$work/first$es.out" || fail "es$es: the line names the folder"
    entries=$(find "$cache" -name '*.pxbin' | wc -l)
    [ "$entries" = "$compiled" ] || fail "es$es: $entries entries stored for $compiled programs"

    run second$es --es $es --program-cache "$cache" || continue
    grep -q "0 compiled, $compiled from the binary cache" "$work/second$es.out" ||
        fail "es$es second run not from the binary cache: $(grep '^programs' "$work/second$es.out")"
    cmp -s "$work/first$es.png" "$work/second$es.png" || fail "es$es: the image from binaries differs"

    # Flip a payload byte (the header is 32 bytes), then truncate: each is rebuilt.
    entry=$(find "$cache" -name '*.pxbin' | head -1)
    byte=$(od -An -tu1 -j100 -N1 "$entry" | tr -d ' ')
    printf "\\$(printf %03o $((byte ^ 255)))" | dd of="$entry" bs=1 seek=100 conv=notrunc status=none
    run flipped$es --es $es --program-cache "$cache" || continue
    [ "$(field flipped$es 3)" = 1 ] && grep -q "fails its authentication" "$work/flipped$es.out" ||
        fail "es$es flipped byte: $(grep '^programs' "$work/flipped$es.out")"
    cmp -s "$work/first$es.png" "$work/flipped$es.png" || fail "es$es: the image after a rebuild differs"
    truncate -s 20 "$entry"
    run truncated$es --es $es --program-cache "$cache" || continue
    [ "$(field truncated$es 3)" = 1 ] || fail "es$es truncated entry: $(grep '^programs' "$work/truncated$es.out")"
    run after$es --es $es --program-cache "$cache" || continue
    grep -q "0 compiled, $compiled from the binary cache" "$work/after$es.out" ||
        fail "es$es: the rebuilt entry is not loaded again: $(grep '^programs' "$work/after$es.out")"
    echo "ok: es$es: stored, loaded, a flipped and a truncated entry rebuilt"
done

# The folder is private and holds the key every entry is authenticated with.
cache="$work/cache_es3"
[ "$(stat -c %a "$cache")" = 700 ] || fail "the cache folder is mode $(stat -c %a "$cache"), not 700"
[ "$(stat -c %a "$cache/key")" = 600 ] && [ "$(stat -c %s "$cache/key")" = 16 ] ||
    fail "the key is mode $(stat -c %a "$cache/key"), $(stat -c %s "$cache/key") bytes"
# An entry written under another folder's key (what anyone who can write
# the folder but cannot read its key can make) is refused, not loaded.
run other --es 3 --program-cache "$work/other_cache" >/dev/null || true
for entry in "$work"/other_cache/*.pxbin; do cp "$entry" "$cache/"; done
run forged --es 3 --program-cache "$cache" &&
    { grep -q "fails its authentication" "$work/forged.out" && [ "$(field forged 2)" = 0 ] ||
        fail "an entry made under another key: $(grep -A1 '^programs' "$work/forged.out")"; }
cmp -s "$work/first3.png" "$work/forged.png" || fail "the image after refusing forged entries differs"
# An entry that is not this user's is not read.
entry=$(find "$cache" -name '*.pxbin' | head -1)
chown 65534 "$entry" 2>/dev/null && {
    run foreign --es 3 --program-cache "$cache" &&
        grep -q "belongs to user 65534" "$work/foreign.err" || fail "an entry of another user was read: $(cat "$work/foreign.err")"
}
# A key others can read, or a folder others can write: no binaries, a warning.
chmod 644 "$cache/key"
run readable_key --es 3 --program-cache "$cache" &&
    { grep -q "readable or writable by other users" "$work/readable_key.err" && [ "$(field readable_key 2)" = 0 ] ||
        fail "a key readable by others was used: $(cat "$work/readable_key.err")"; }
chmod 600 "$cache/key"
chmod 777 "$cache"
run open_folder --es 3 --program-cache "$cache" &&
    { grep -q "writable by other users" "$work/open_folder.err" || fail "a folder writable by others was used"; }
chmod 700 "$cache"
echo "ok: private folder and key; forged, foreign and exposed caches refused"

run off --program-cache off && grep -q "from the binary cache (off)" "$work/off.out" || fail "--program-cache off"

# A folder that cannot be made (its parent is a file): a warning, not a failure.
touch "$work/file"
if run unwritable --program-cache "$work/file/programs"; then
    grep -q "warning: program binary cache" "$work/unwritable.err" || fail "no warning for an unwritable folder"
    echo "ok: an unwritable cache folder is a warning: $(head -1 "$work/unwritable.err")"
fi

# The default folder: $XDG_CACHE_HOME/parallaxes/programs, else ~/.cache/parallaxes/programs.
run xdg && [ -n "$(find "$XDG_CACHE_HOME/parallaxes/programs" -name '*.pxbin' 2>/dev/null)" ] ||
    fail "no entry under \$XDG_CACHE_HOME/parallaxes/programs"
env -u XDG_CACHE_HOME "$parallax" render default --size 16x16 --frames 1 -o "$work/home.png" >"$work/home.out" 2>&1 &&
    [ -n "$(find "$HOME/.cache/parallaxes/programs" -name '*.pxbin' 2>/dev/null)" ] ||
    fail "no entry under \$HOME/.cache/parallaxes/programs: $(cat "$work/home.out")"

[ "$failures" = 0 ] && echo "the program binary cache behaves" || { echo "$failures program cache case(s) failed"; exit 1; }
