#!/usr/bin/env bash
# Builds the JavaScript the report page (`fem2rbd report`, src/report/) inlines:
# three.js and its OrbitControls, from the npm registry at the versions pinned in
# scripts/report-js/package.json and package-lock.json (npm ci checks each package's
# integrity hash), bundled and minified by esbuild (pinned there too) from
# scripts/report-js/entry.mjs into one classic script that defines the global `THREE`.
#
#   bash scripts/update-report-js.sh          rebuilds, and checks that the result is the
#                                             committed data/report/three-bundle.min.js
#                                             (its SHA-256 in data/report/SHA256SUMS)
#   bash scripts/update-report-js.sh --write  rebuilds and replaces the committed files
#                                             (bundle, three.js's licence, SHA256SUMS)
#
# The binary never runs node: it embeds the committed bundle (include_str!).
# Needs Node.js >= 18 and npm.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
src="$here/scripts/report-js"
dst="$here/data/report"
mode="${1:-check}"
case "$mode" in check | --write) ;; *) echo "usage: $0 [--write]" >&2; exit 2 ;; esac

npm ci --prefix "$src" --no-audit --no-fund --silent
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$src/node_modules/.bin/esbuild" "$src/entry.mjs" --bundle --minify --format=iife \
  --legal-comments=eof --target=es2020 --log-level=warning --outfile="$tmp/three-bundle.min.js"
cp "$src/node_modules/three/LICENSE" "$tmp/three-LICENSE"
if grep -qi '</script' "$tmp/three-bundle.min.js"; then
  echo "update-report-js.sh: the bundle contains '</script' and cannot be inlined" >&2
  exit 1
fi
(cd "$tmp" && sha256sum three-bundle.min.js three-LICENSE > SHA256SUMS)

if [ "$mode" = --write ]; then
  cp "$tmp/three-bundle.min.js" "$tmp/three-LICENSE" "$tmp/SHA256SUMS" "$dst/"
  echo "wrote $dst: $(cat "$dst/SHA256SUMS" | tr '\n' ' ')"
else
  (cd "$dst" && sha256sum -c --quiet SHA256SUMS) || {
    echo "update-report-js.sh: committed files in $dst do not match SHA256SUMS" >&2; exit 1; }
  cmp -s "$tmp/SHA256SUMS" "$dst/SHA256SUMS" || {
    echo "update-report-js.sh: the pinned packages build a different bundle:" >&2
    diff "$dst/SHA256SUMS" "$tmp/SHA256SUMS" >&2 || true
    exit 1; }
  echo "ok: $dst matches the pinned build ($(head -c 16 "$dst/SHA256SUMS")…)"
fi
