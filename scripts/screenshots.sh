#!/usr/bin/env bash
# Remakes the README's screenshots (docs/images/) with the browser-test tooling: runs a Barthel
# test with scripts/launch.sh --wait-start, presses Start on the dashboard from headless
# Chromium (Playwright), and photographs the DSR viewer and the dashboard.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" --with-browser >/dev/null
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
exec python "$root/scripts/screenshots.py" "$@"
