#!/usr/bin/env bash
# railvti set-up and everyday tasks. Each task first installs what is missing:
# Debian packages (apt), a virtual environment in .venv, and the build.
#
#   ./dev.sh run        run the main job (inputs/default.nml) -> results/: HDF5, plots, summary
#   ./dev.sh test       run the test suite
#   ./dev.sh validate   run the validation scripts (charts in validation/figures)
#   ./dev.sh bench      run the benchmark scripts
#   ./dev.sh lint       ruff check and ruff format --check (pyproject.toml [tool.ruff])
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$(pwd)
VENV="$ROOT/.venv"
PY="$VENV/bin/python"
APT_PKGS=(gfortran libfftw3-dev libopenblas-dev liblapack-dev libarpack2-dev pkg-config)

log() { printf '[railvti] %s\n' "$*" >&2; }

ensure_system() {
    local missing=() p
    for p in "${APT_PKGS[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
    done
    local python=${PYTHON:-python3}
    if ! command -v "$python" >/dev/null 2>&1; then
        missing+=(python3 python3-dev)
    fi
    if command -v "$python" >/dev/null 2>&1 && ! "$python" -c 'import venv, ensurepip' 2>/dev/null; then
        missing+=(python3-venv)
    fi
    if ((${#missing[@]})); then
        local sudo=""
        [ "$(id -u)" -ne 0 ] && sudo="sudo"
        log "installing Debian packages: ${missing[*]}"
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}" >/dev/null
    fi
}

ensure_venv() {
    if [ ! -x "$PY" ]; then
        log "creating the virtual environment in .venv"
        "${PYTHON:-python3}" -m venv "$VENV"
    fi
    if ! "$PY" -c 'import mesonpy, numpy, pytest, h5py, f90nml, tqdm, matplotlib, scipy, triangle, dask, distributed, threadpoolctl, ruff' 2>/dev/null; then
        log "installing Python packages"
        "$PY" -m pip install -q --upgrade pip
        "$PY" -m pip install -q "meson-python>=0.15" "meson>=1.1" ninja "numpy>=1.26" \
            "scipy>=1.11" "h5py>=3.9" "matplotlib>=3.7" "f90nml>=1.4" "tqdm>=4.60" "pytest>=7" "triangle>=20230923" \
            "dask>=2024.1" "distributed>=2024.1" "threadpoolctl>=3.1" "ruff>=0.6"
    fi
}

ensure_build() {
    # The build folder persists, so a rebuild only compiles what changed.
    log "building and installing railvti"
    "$PY" -m pip install -q --no-build-isolation --no-deps -Cbuild-dir=build/release . >/dev/null
}

setup() { ensure_system; ensure_venv; ensure_build; }

task=${1:-help}
shift || true
case "$task" in
    run)
        setup
        mkdir -p results
        # the main job: cases and sweep points as tasks on a Dask LocalCluster (one per core)
        "$VENV/bin/railvti" run inputs/default.nml -o results/default.h5 "$@"
        "$VENV/bin/railvti" plot results/default.h5 -o results >/dev/null
        echo
        "$VENV/bin/railvti" summary results/default.h5 --plots results
        ;;
    test)
        setup
        # Tests import the installed package; they run from tests/, outside python/.
        cd "$ROOT/tests"
        "$PY" -m pytest -q "$@"
        ;;
    validate)
        setup
        for s in validation/*.py; do log "validation: $s"; "$PY" "$s" "$@"; done
        ;;
    bench)
        setup
        for s in benchmarks/*.py; do log "benchmark: $s"; "$PY" "$s" "$@"; done
        ;;
    lint)
        ensure_venv
        "$PY" -m ruff check python tests validation benchmarks
        "$PY" -m ruff format --check python tests validation benchmarks
        ;;
    setup)
        setup
        ;;
    *)
        sed -n '2,10p' "$0"
        ;;
esac
