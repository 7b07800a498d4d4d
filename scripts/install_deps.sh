#!/usr/bin/env bash
# Installs every Debian package CulinaryCut needs (Debian 12 bookworm); with --tests also those only the
# test suite needs. Idempotent, non-interactive.
# Runs apt as root, or through sudo when not root.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

PACKAGES=(
  build-essential cmake pkg-config git
  # wire API
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  # engine
  libeigen3-dev libbullet-dev liburdfdom-dev nlohmann-json3-dev
  # server
  libzmq3-dev cppzmq-dev libspdlog-dev libfmt-dev libcli11-dev libssl-dev
  # renderer: headless EGL (Mesa llvmpipe without a GPU), image and video encoding, mesh files
  libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri libopencv-dev libassimp-dev
  # tests and benchmarks
  catch2 libbenchmark-dev
  # Python client: Debian's packages, plus a project virtualenv for what Debian lacks (requirements/pypi.txt)
  python3 python3-venv python3-grpcio python3-grpc-tools python3-protobuf python3-numpy python3-zmq python3-pytest python3-opencv python3-jsonschema
  # plots in benchmarks, docs and examples
  python3-matplotlib python3-pil
  # dataset files (HDF5: robomimic/LIBERO and RDT layouts)
  python3-h5py
  # the safety module's force-model fit (scipy.optimize.nnls)
  python3-scipy
  # the learned policy (learning/): PyTorch and torchvision, CPU builds; no weights are downloaded
  python3-torch python3-torchvision
)
# Only the test suite needs these (scripts/test.sh passes --tests): the HTML benchmark report is
# checked in a real headless browser, the fuzz targets build with clang, libFuzzer and sanitizers, and
# docker-compose.yml is read (YAML) to check it against the Compose schema.
TEST_PACKAGES=(chromium chromium-driver python3-selenium clang libclang-rt-14-dev libomp-14-dev python3-yaml)
if [ "${1:-}" = "--tests" ]; then PACKAGES+=("${TEST_PACKAGES[@]}"); fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

install_python_env() {
  # The project virtualenv: Debian's Python packages stay visible (--system-site-packages); PyPI adds
  # only the pinned packages Debian lacks or has too old. Reinstalls only when the pins change.
  local venv="$root/.venv"
  local pins="$root/requirements/pypi.txt"
  if [ ! -x "$venv/bin/python" ]; then
    /usr/bin/python3 -m venv --system-site-packages "$venv"
  fi
  if ! cmp -s "$pins" "$venv/.installed-pins"; then
    echo "install_deps: installing the pinned PyPI packages into $venv"
    "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$pins"
    cp "$pins" "$venv/.installed-pins"
  fi
  # The culinarycut package itself, editable: its build generates the gRPC stubs with Debian's grpc_tools
  # (--no-build-isolation), which match Debian's protobuf and grpcio; --no-index: those come from Debian.
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --no-index \
    -e "$root/client/python"
  # The policy adapters (policies/), editable too: registers openvla, openvla-oft, octo, rdt, openpi for `--policy`.
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --no-index \
    -e "$root/policies"
  # The learned policy (learning/), editable too: `python -m culinarycut_learning train|serve` (Debian's torch).
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --no-index \
    -e "$root/learning"
}

missing=()
for package in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} Debian packages already installed"
else
  echo "install_deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  # `env` carries the variable through sudo, whose env_reset would drop it.
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
install_python_env
