#!/usr/bin/env bash
# The pure-logic test binaries must not load any GL or EGL library: they link
# the GL-free core alone. Fails naming the binary and the library it found.
set -euo pipefail
status=0
for binary in "$@"; do
    libs=$(ldd "$binary") || { echo "FAIL: ldd could not read $binary"; exit 1; }
    if [ -z "$libs" ]; then echo "FAIL: ldd listed nothing for $binary"; exit 1; fi
    # A positive control: every dynamic C++ binary loads libc, so an ldd that
    # printed something else (an error, a format change) is caught here.
    if ! grep -q 'libc\.so' <<<"$libs"; then echo "FAIL: no libc in ldd output of $binary"; exit 1; fi
    if found=$(grep -E 'lib(GLESv[123]|GLESv2|EGL|GL|GLX|OpenGL|gbm)[._]' <<<"$libs"); then
        echo "FAIL: $binary loads a GL library:"; echo "$found"; status=1
    else
        echo "ok: $(basename "$binary") loads no GL or EGL library"
    fi
done
exit $status
