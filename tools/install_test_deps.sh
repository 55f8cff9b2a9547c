#!/usr/bin/env bash
# Installs what building and testing raycast needs on Debian/Ubuntu, only when it is missing:
# CMake, a C++ compiler, GoogleTest, libpng (optional: PNG output), cpp-httplib (optional: the
# viewer) and, for the viewer's browser test, Chromium, ChromeDriver and Selenium. The renderer
# itself needs only CMake and a compiler; run_all.sh does not call this.
set -euo pipefail

missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v c++ >/dev/null || missing+=(g++)
command -v make >/dev/null || missing+=(make)
[ -e /usr/include/gtest/gtest.h ] || missing+=(libgtest-dev)
[ -e /usr/include/png.h ] || missing+=(libpng-dev)
# Optional: the viewer (raycast view) needs cpp-httplib, found through pkg-config, and its browser
# test a headless Chromium driven by Selenium. Without them those tests skip, so a failure to
# install them (a distribution that packages Chromium as a snap, say) is not fatal.
optional=()
[ -e /usr/include/httplib.h ] || optional+=(libcpp-httplib-dev)
command -v pkg-config >/dev/null || optional+=(pkg-config)
command -v chromium >/dev/null || optional+=(chromium)
command -v chromedriver >/dev/null || optional+=(chromium-driver)
/usr/bin/python3 -c "import selenium" 2>/dev/null || optional+=(python3-selenium)
if [ "${1:-}" = "--fuzz" ]; then
  command -v clang++ >/dev/null || missing+=(clang)
  compgen -G "/usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a" >/dev/null || missing+=(libclang-rt-dev)
fi

if [ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ]; then
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq || true
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_test_deps: installing ${missing[*]}" >&2
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [ ${#optional[@]} -gt 0 ]; then
  echo "install_test_deps: installing ${optional[*]} (optional: the viewer and its browser test)" >&2
  $sudo apt-get install -y -qq --no-install-recommends "${optional[@]}" >/dev/null ||
    echo "install_test_deps: could not install ${optional[*]}: the viewer's tests will skip" >&2
fi
