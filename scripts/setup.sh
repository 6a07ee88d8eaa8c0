#!/usr/bin/env bash
# Installs patlab's build, test and plotting dependencies: Debian 12 packages only.
# Run as root (or with sudo available). Idempotent. `--bench` adds OpenCV, which only the
# vision benchmark uses for its side-by-side comparison, and libspng, which it times beside
# libpng; the tool itself needs neither.
set -euo pipefail
packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libboost-program-options-dev libboost-math-dev libtbb-dev
  libtomlplusplus-dev librandom123-dev nlohmann-json3-dev libpng-dev libjpeg-dev
  libceres-dev libnlopt-dev libgtest-dev libgmock-dev libbenchmark-dev clang-format clang-tidy clang
  python3 python3-numpy python3-scipy python3-matplotlib python3-pytest
  libprotobuf-dev protobuf-compiler python3-protobuf libavformat-dev libavcodec-dev libswscale-dev
  libavutil-dev libv4l-dev
  pybind11-dev python3-pybind11 python3-dev python3-pandas python3-nbconvert python3-ipykernel
  parallel slurm-wlm munge locales strace
)
if [[ "${1:-}" == "--bench" ]]; then packages+=(libopencv-dev libspng-dev); fi

sudo_cmd=()
if [[ "$(id -u)" -ne 0 ]]; then sudo_cmd=(sudo); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  "${sudo_cmd[@]}" apt-get update
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi

# The locale tests run patlab under de_DE.UTF-8 (a decimal comma) and expect the bytes of the C
# locale: generate it once.
if ! locale -a 2>/dev/null | grep -qi '^de_DE\.utf-\?8$'; then
  "${sudo_cmd[@]}" sed -i 's/^# *\(de_DE\.UTF-8 UTF-8\)/\1/' /etc/locale.gen
  grep -q '^de_DE\.UTF-8 UTF-8' /etc/locale.gen ||
    echo 'de_DE.UTF-8 UTF-8' | "${sudo_cmd[@]}" tee -a /etc/locale.gen > /dev/null
  "${sudo_cmd[@]}" locale-gen
fi
