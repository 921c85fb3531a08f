#!/usr/bin/env bash
# The viewer page in a real browser (docs/web.md): builds the page (make web),
# installs puppeteer-core (tests/web/package-lock.json) and Debian's chromium
# where missing, and runs tests/web/web_test.mjs against the native goldens
# with build/parallax (make build). Not part of `make test`: .ci/run calls it.
#   bash tests/web/run.sh [--screenshot docs/web-viewer.png] [--webgl 2,1]
set -euo pipefail
cd "$(dirname "$0")/../.."
missing=()
for p in emscripten chromium; do
  dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q '^install ok installed$' || missing+=("$p")
done
# node and npm may come from Debian or from elsewhere (a newer nodejs with its own npm).
command -v node >/dev/null || missing+=(nodejs)
command -v npm >/dev/null || missing+=(npm)
if ((${#missing[@]})); then
  if [ "$(id -u)" != 0 ]; then
    echo "web test: missing Debian packages; as root: apt-get install -y ${missing[*]}" >&2
    exit 2
  fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}" >/dev/null ||
    { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}" >/dev/null; }
fi
if [ ! -x build/parallax ]; then
  echo "web test: build/parallax is missing (make build): it compares the page's images with the goldens" >&2
  exit 2
fi
make --no-print-directory web
if [ ! -d tests/web/node_modules/puppeteer-core ]; then
  (cd tests/web && npm ci --no-audit --no-fund --loglevel=error)
fi
node tests/web/web_test.mjs --page build-web/web --parallax build/parallax --out out/web "$@"
