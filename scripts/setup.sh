#!/usr/bin/env bash
# Installs what fem2rbd needs to build and test on Debian 12 (bookworm). Idempotent: it
# only installs what is missing, so a second run takes a second or two.
#
#   apt: libbullet-dev (Bullet 3.24, double-precision libs + bullet-float64.pc),
#        libeigen3-dev (header-only; the shim's direct joint solve, SimplicialLDLT),
#        pkg-config, libclang-dev and clang (bindgen at build time), g++ (the C++
#        shim; gcc links Rust binaries), python3 + pip,
#        slurmctld slurmd slurm-client munge (tests/it/study/slurm.rs brings up a
#        single-node Slurm; installed without starting any daemon),
#        curl + ca-certificates (only when Rust must be installed)
#   pip: pybullet==3.2.7 and numpy (pybullet cross-checks), openseespy (OpenSees
#        cross-checks of the FE stages), meshio==5.3.5 (reads back our VTK files)
#        matplotlib (plots of the comparison scripts, e.g. scripts/library-opensees.py)
#   apt: chromium (Debian's; headless, the report page's browser test tests/it/report/browser.rs)
#   apt: libblas3, liblapack3 (openseespy's wheel links against them)
#   npm: scripts/setup-node.sh (gltf-validator and three.js for the glTF checks,
#        playwright-core for the report page's browser test)
#   Rust: a toolchain >= 1.85 via rustup, only when cargo is missing or older
#
# Run as root, or as a user with sudo.
set -euo pipefail

log() { printf 'setup: %s\n' "$*"; }

if [ "$(id -u)" -eq 0 ]; then
    SUDO=()
else
    command -v sudo >/dev/null 2>&1 || { echo "setup: not root and no sudo" >&2; exit 1; }
    SUDO=(sudo)
fi

# ---- apt packages ------------------------------------------------------------------
apt_missing() {
    local p
    for p in "$@"; do
        if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
            printf '%s\n' "$p"
        fi
    done
}

# g++ compiles the C++ shim (the cc crate calls `c++`) and gcc links Rust binaries.
# libblas3 and liblapack3: the shared libraries openseespy's wheel links against (it does
# not bundle them).
APT_PACKAGES=(libbullet-dev libeigen3-dev libclang-dev clang pkg-config g++ chromium libblas3 liblapack3)
# A python3 with pip from elsewhere (pyenv, venv) is fine; otherwise take Debian's.
if ! { command -v python3 >/dev/null 2>&1 && python3 -m pip --version >/dev/null 2>&1; }; then
    APT_PACKAGES+=(python3 python3-pip)
fi
mapfile -t missing < <(apt_missing "${APT_PACKAGES[@]}")
need_rust=0
if ! command -v cargo >/dev/null 2>&1 && [ -f "$HOME/.cargo/env" ]; then
    # shellcheck disable=SC1091
    . "$HOME/.cargo/env"
fi
if command -v cargo >/dev/null 2>&1; then
    ver=$(cargo --version | awk '{print $2}')
    major=${ver%%.*}; rest=${ver#*.}; minor=${rest%%.*}
    if [ "$major" -lt 1 ] || { [ "$major" -eq 1 ] && [ "$minor" -lt 85 ]; }; then need_rust=1; fi
else
    need_rust=1
fi
if [ "$need_rust" -eq 1 ]; then
    mapfile -t more < <(apt_missing curl ca-certificates)
    missing+=("${more[@]}")
fi
if [ "${#missing[@]}" -gt 0 ]; then
    log "apt-get install ${missing[*]}"
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}"
else
    log "apt packages present"
fi

# Slurm for tests/it/study/slurm.rs: the daemons are started by the test itself, so apt must
# not start them (no systemd here): a policy-rc.d that refuses, only while installing and
# only if none exists.
mapfile -t slurm_missing < <(apt_missing slurmctld slurmd slurm-client munge)
if [ "${#slurm_missing[@]}" -gt 0 ]; then
    log "apt-get install --no-install-recommends ${slurm_missing[*]}"
    own_policy=0
    if [ ! -e /usr/sbin/policy-rc.d ]; then
        printf '#!/bin/sh\nexit 101\n' | "${SUDO[@]}" tee /usr/sbin/policy-rc.d >/dev/null
        "${SUDO[@]}" chmod 755 /usr/sbin/policy-rc.d
        own_policy=1
    fi
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${slurm_missing[@]}"
    if [ "$own_policy" -eq 1 ]; then "${SUDO[@]}" rm -f /usr/sbin/policy-rc.d; fi
else
    log "slurm packages present"
fi

# ---- Rust ----------------------------------------------------------------------------
if [ "$need_rust" -eq 1 ]; then
    log "installing Rust (rustup, stable, minimal profile)"
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh -s -- -y --profile minimal -c rustfmt,clippy
    # shellcheck disable=SC1091
    . "$HOME/.cargo/env"
else
    log "Rust present: $(cargo --version)"
fi

# ---- pip packages ----------------------------------------------------------------------
mapfile -t pip_missing < <(python3 - <<'PY'
import importlib.metadata as md
need = {"pybullet": "3.2.7", "numpy": None, "openseespy": None, "meshio": "5.3.5",
        "matplotlib": None}
for name, version in need.items():
    try:
        have = md.version(name)
    except md.PackageNotFoundError:
        have = None
    if have is None or (version is not None and have != version):
        print(name if version is None else f"{name}=={version}")
PY
)
if [ "${#pip_missing[@]}" -gt 0 ]; then
    log "pip install ${pip_missing[*]}"
    pip_install() { python3 -m pip install --quiet --disable-pip-version-check "$@"; }
    if [ "$(id -u)" -eq 0 ]; then pip_cmd=(pip_install); else pip_cmd=(pip_install --user); fi
    if ! out=$("${pip_cmd[@]}" "${pip_missing[@]}" 2>&1); then
        if printf '%s' "$out" | grep -q 'externally-managed-environment'; then
            log "pip: externally managed Python; retrying with --break-system-packages"
            "${pip_cmd[@]}" --break-system-packages "${pip_missing[@]}"
        else
            printf '%s\n' "$out" >&2
            exit 1
        fi
    fi
else
    log "pip packages present (pybullet 3.2.7, numpy, openseespy, meshio)"
fi

# ---- checks -----------------------------------------------------------------------------
pkg-config --exists bullet-float64 || { echo "setup: pkg-config cannot find bullet-float64" >&2; exit 1; }
python3 -c 'import numpy, pybullet' >/dev/null 2>&1 || { echo "setup: python3 cannot import numpy and pybullet" >&2; exit 1; }
python3 -c 'import openseespy.opensees' >/dev/null 2>&1 || { echo "setup: python3 cannot import openseespy.opensees (its shared libraries: ldd on openseespylinux/opensees*.so)" >&2; exit 1; }
log "ok: Bullet $(pkg-config --modversion bullet-float64) (double), $(python3 --version)"

# ---- npm packages (glTF validator, three.js) -------------------------------------------
bash "$(dirname "${BASH_SOURCE[0]}")/setup-node.sh"
