#!/usr/bin/env bash
# Installs the npm packages the tests use, at the versions pinned in each folder's
# package.json and package-lock.json, into its node_modules:
#   tests/gltf:   gltf-validator  the Khronos glTF validator (tests/gltf/validate.mjs,
#                                 tests/it/output/gltf_validator.rs)
#                 three           three.js, whose GLTFLoader plays our files
#                                 (tests/gltf/three_sample.mjs, tests/it/output/gltf_three.rs)
#   tests/report: playwright-core drives headless Chromium over the report page
#                                 (tests/report/check.mjs, tests/it/report/browser.rs)
# Needs Node.js >= 18 and npm (Debian/Ubuntu: `apt-get install nodejs npm`).
# Idempotent: does nothing when the pinned versions are already installed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  if command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
    apt-get update -qq && apt-get install -y -qq nodejs npm
  fi
fi
command -v node >/dev/null || { echo "setup-node.sh: node not found; install Node.js >= 18" >&2; exit 1; }
command -v npm >/dev/null || { echo "setup-node.sh: npm not found; install npm" >&2; exit 1; }

# Prints "name@version" for each pinned dependency: wanted (package.json) or installed.
versions() {
  node -e '
    const path = require("path");
    const dir = process.argv[1], which = process.argv[2];
    const deps = require(path.join(dir, "package.json")).dependencies;
    for (const [name, want] of Object.entries(deps)) {
      let v = want;
      if (which === "have") {
        try { v = require(path.join(dir, "node_modules", name, "package.json")).version; }
        catch { v = "none"; }
      }
      console.log(`${name}@${v}`);
    }' "$prefix" "$1"
}

for prefix in "$here/tests/gltf" "$here/tests/report"; do
  if [ "$(versions have)" = "$(versions want)" ]; then
    echo "already installed in $prefix/node_modules:" $(versions have)
    continue
  fi
  # `npm ci` installs exactly what package-lock.json pins (integrity-checked).
  npm ci --prefix "$prefix" --no-audit --no-fund
  [ "$(versions have)" = "$(versions want)" ] || {
    echo "setup-node.sh: installed versions differ from package.json:" $(versions have) >&2
    exit 1
  }
  echo "installed in $prefix/node_modules:" $(versions have)
done
