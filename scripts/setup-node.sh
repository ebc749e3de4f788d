#!/usr/bin/env bash
# Installs the Khronos glTF validator (npm package `gltf-validator`, version pinned in
# tests/gltf/package.json and package-lock.json) into tests/gltf/node_modules, where
# tests/gltf/validate.mjs and the Rust test tests/gltf_validator.rs find it.
# Needs Node.js >= 18 and npm (Debian/Ubuntu: `apt-get install nodejs npm`).
# Idempotent: does nothing when the pinned version is already installed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
prefix="$here/tests/gltf"

command -v node >/dev/null || { echo "setup-node.sh: node not found; install Node.js >= 18" >&2; exit 1; }
command -v npm >/dev/null || { echo "setup-node.sh: npm not found; install npm" >&2; exit 1; }

want="$(node -e 'console.log(require(process.argv[1]).dependencies["gltf-validator"])' "$prefix/package.json")"
have="$(node -e 'try { console.log(require(process.argv[1]).version) } catch { console.log("none") }' \
  "$prefix/node_modules/gltf-validator/package.json")"
if [ "$have" = "$want" ]; then
  echo "gltf-validator $have already installed in $prefix/node_modules"
  exit 0
fi

# `npm ci` installs exactly what package-lock.json pins (integrity-checked).
npm ci --prefix "$prefix" --no-audit --no-fund
echo "installed gltf-validator $(node -e 'console.log(require(process.argv[1]).version)' \
  "$prefix/node_modules/gltf-validator/package.json") in $prefix/node_modules"
