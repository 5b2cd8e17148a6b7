#!/bin/sh
# scripts/install-deps.sh - the Debian 12 packages hovox needs, by group.
#   scripts/install-deps.sh [--check] [build] [test] [bench] [browser] [fuzz]   (no group: build,
#   test, bench, browser; fuzz is clang for `make fuzz`, browser chromium for the viewer's tests)
# Installs what is missing when run as root (apt-get update once, then apt-get install -y
# --no-install-recommends); otherwise prints the exact command and exits 1. --check only
# reports (exit 1 when something is missing).
set -eu

BUILD_PKGS="make gcc g++ pkg-config libopenvdb-dev libtbb-dev libopenimageio-dev libvtk9-dev \
libpng-dev libdeflate-dev zlib1g-dev liblua5.4-dev libcairo2-dev libjansson-dev libzip-dev libblosc-dev libxml2-dev libjpeg-dev liblcms2-dev libgs-common libpolyclipping-dev fonts-dejavu-core"
TEST_PKGS="libcriterion-dev libopenvdb-tools openimageio-tools libopenmpi-dev openmpi-bin python3 python3-numpy \
python3-scipy python3-openvdb python3-vtk9 libxml2-utils unzip lib3mf-dev time bsdutils \
python3-dev python3-setuptools python3-wheel python3-pip python3-venv python3-pytest \
python3-nibabel python3-pydicom"
BENCH_PKGS="admesh prusa-slicer hyperfine time lib3mf-dev libspng-dev"
# the browser tests of hovox view's pages (make browser-tests): CI installs and requires them;
# without them `make test` skips those tests with a message
BROWSER_PKGS="chromium python3-pil"
FUZZ_PKGS="clang"

check=0
groups=""
for a in "$@"; do
    case "$a" in
    --check) check=1 ;;
    build | test | bench | browser | fuzz) groups="$groups $a" ;;
    *) echo "install-deps.sh: unknown argument '$a' (groups: build test bench browser fuzz; --check)" >&2; exit 2 ;;
    esac
done
[ -n "$groups" ] || groups="build test bench browser"

pkgs=""
for g in $groups; do
    case "$g" in
    build) pkgs="$pkgs $BUILD_PKGS" ;;
    test) pkgs="$pkgs $TEST_PKGS" ;;
    bench) pkgs="$pkgs $BENCH_PKGS" ;;
    browser) pkgs="$pkgs $BROWSER_PKGS" ;;
    fuzz) pkgs="$pkgs $FUZZ_PKGS" ;;
    esac
done

missing=""
for p in $pkgs; do
    st=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
    [ "$st" = "installed" ] || missing="$missing $p"
done
[ -z "$missing" ] && exit 0

cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends$missing"
if [ "$check" = 1 ]; then
    echo "missing Debian packages:$missing" >&2
    exit 1
fi
if [ "$(id -u)" != 0 ]; then
    echo "hovox needs these Debian packages:$missing" >&2
    echo "run as root:" >&2
    echo "  $cmd" >&2
    exit 1
fi
echo "installing:$missing" >&2
apt-get update
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $missing
