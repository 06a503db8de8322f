#!/usr/bin/env bash
# The documentation site (mkdocs.yml; MkDocs with the Material theme, pinned in requirements.txt):
#   scripts/docs.sh            build it offline into site/ (strict: a broken link fails); open
#                              site/index.html
#   scripts/docs.sh --serve    build it and serve it on http://127.0.0.1:8000, rebuilt on edits
# The reference pages of the nodes and command lines are generated from the code at each build
# (docs/reference/generate.py).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" > /dev/null
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
cd "$root"
# MkDocs 1.6 and Material 9 print a notice about their successors at every build: the site is
# pinned to them (requirements.txt), so the notice is kept out of the output
export NO_MKDOCS_2_WARNING=1 DISABLE_MKDOCS_2_WARNING=true
if [ "${1:-}" = "--serve" ]; then
  exec mkdocs serve --strict --dev-addr 127.0.0.1:8000
fi
mkdocs build --strict --quiet
echo "[docs] built: $root/site/index.html"
