#!/usr/bin/env bash
# Make sure a Chromium for the headless browser tests of the 3-D viewer is on this machine:
# Debian's `chromium` package, installed with apt-get if /usr/bin/chromium is missing.
# Idempotent; prints the path of the browser on its last line. Needs Debian's package
# archive the first time (run as root, or with sudo available).
set -euo pipefail
browser=/usr/bin/chromium
if [ ! -x "$browser" ]; then
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        sudo="sudo"
    fi
    echo "==> installing Debian's chromium package with apt-get" >&2
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq >&2
    $sudo apt-get install -y -qq --no-install-recommends chromium fonts-dejavu-core >&2
fi
"$browser" --version >&2
echo "$browser"
