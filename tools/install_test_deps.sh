#!/usr/bin/env bash
# Installs what building and testing raycast needs on Debian/Ubuntu, only when it is missing:
# CMake, a C++ compiler, GoogleTest, and libpng (optional: PNG output). The renderer itself needs
# only CMake and a compiler; run_all.sh does not call this.
set -euo pipefail

missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v c++ >/dev/null || missing+=(g++)
command -v make >/dev/null || missing+=(make)
[ -e /usr/include/gtest/gtest.h ] || missing+=(libgtest-dev)
[ -e /usr/include/png.h ] || missing+=(libpng-dev)
if [ "${1:-}" = "--fuzz" ]; then
  command -v clang++ >/dev/null || missing+=(clang)
  compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null || missing+=(libclang-rt-dev)
fi

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install_test_deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
