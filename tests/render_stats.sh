#!/usr/bin/env bash
# `parallax render --stats`: one preparation and one plan per object for a
# render, and no program built that is not drawn (issue 19). The counts come
# from the library's pipeline counters; the expected ones from the render's
# own listing of objects and materials.
set -euo pipefail
parallax=$1
status=0
for scene in default showcase "$(dirname "$0")/../examples/scenes/cones.json"; do
    out=$("$parallax" render "$scene" --stats --frames 2 --size 128x128 --program-cache off -o "$(mktemp -d)/x.png")
    stats=$(grep '^pipeline' <<<"$out" || true)
    [ -n "$stats" ] || { echo "FAIL: $scene: no pipeline line in:"; echo "$out"; exit 1; }
    objects=$(grep -c '^object ' <<<"$out" || true)
    materials=$(grep '^object ' <<<"$out" | sed -E 's/.* material +([^ ]+) .*/\1/' | sort -u | wc -l)
    drawn=$(grep '^frame' <<<"$out" | sed -E 's/.*, ([0-9]+) program\(s\);.*/\1/')
    number() { sed -E "s/.* ([0-9]+) $1.*/\\1/" <<<"$stats"; }
    check() {
        if [ "$2" != "$3" ]; then echo "FAIL: $scene: $1 $2, expected $3 ($stats)"; status=1; fi
    }
    check validations "$(number 'validation')" 1
    check "material image builds" "$(number 'material image build')" "$materials"
    check "mesh builds" "$(number 'mesh build')" "$objects"
    check "object plans" "$(number 'object plan')" "$objects"
    check "programs built" "$(number 'program\(s\) built')" "$drawn"
    # plan_variant once per material that names its technique (the planner
    # is made once per load; frames reuse its plans).
    named_materials=$(grep '^object ' <<<"$out" | { grep -v 'effects' || true; } | sed -E 's/.* material +([^ ]+) .*/\1/' | sort -u | wc -l)
    check "named material plans" "$(number 'named material plan')" "$named_materials"
    [ $status -eq 0 ] && echo "ok: $scene: $stats"
done
exit $status
