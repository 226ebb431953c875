#!/usr/bin/env bash
# Runs README.md's "The pipeline, by hand" block as written, in OUT_DIR: make demo's first
# picture and the test that keeps docs/images/cornell.png the picture that block makes come
# from the README's own text, so the three cannot drift apart.
# Usage: scripts/readme_chain.sh TOOLS_DIR OUT_DIR
set -euo pipefail
tools=$(cd "${1:-build/apps}" && pwd)
out=${2:-out/demo}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"

# The first ```sh block after the heading, its tools and data found from anywhere.
block=$(awk '/^## The pipeline, by hand/ { section = 1; next }
             section && /^```sh/ { inside = 1; next }
             inside && /^```/ { exit }
             inside { print }' "$here/README.md")
if [ -z "$block" ] || ! grep -q '^B=build/apps$' <<<"$block"; then
  echo "readme_chain.sh: README.md has no \"The pipeline, by hand\" block starting B=build/apps" >&2
  exit 1
fi
block=$(sed -e "s|^B=build/apps\$|B='$tools'|" -e "s|testdata/|'$here'/testdata/|g" <<<"$block")
cd "$out"
# Each command echoed as it runs, as the demo's other steps are.
bash -euo pipefail -x -c "$block"
