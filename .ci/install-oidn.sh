#!/usr/bin/env bash
# Installs Intel Open Image Denoise for the optional `denoise` feature from the
# shared libraries shipped inside the `pyoidn` wheel on PyPI (OIDN is not
# packaged by Debian). Only the CPU device and its TBB runtime are kept.
# Usage: .ci/install-oidn.sh DIR   -> DIR/lib/libOpenImageDenoise.so ...
# Then build with: OIDN_DIR=DIR cargo build --release --features denoise
# and run with:    LD_LIBRARY_PATH=DIR/lib
set -euo pipefail
dir="${1:?usage: install-oidn.sh DIR}"
version="2.5.1.0"
if [ -e "$dir/lib/libOpenImageDenoise.so" ]; then
    exit 0
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 -m pip download --quiet --no-deps "pyoidn==$version" -d "$tmp"
mkdir -p "$dir/lib"
python3 - "$tmp"/pyoidn-*.whl "$dir/lib" <<'PY'
import sys, zipfile, os
wheel, out = sys.argv[1], sys.argv[2]
keep = ("libOpenImageDenoise.so", "libOpenImageDenoise_core.so", "libOpenImageDenoise_device_cpu.so", "libtbb.so")
with zipfile.ZipFile(wheel) as z:
    for name in z.namelist():
        base = os.path.basename(name)
        if name.startswith("pyoidn/oidn/lib/") and base.startswith(keep):
            with open(os.path.join(out, base), "wb") as f:
                f.write(z.read(name))
PY
echo "installed OIDN $version into $dir/lib"
