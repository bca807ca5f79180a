#!/usr/bin/env bash
# Packs what bench/gpu_replay.sh needs on a GPU machine that has none of our Debian packages
# (docs/BENCHMARKS.md, "On a GPU"): subsplat_replay built without OpenImageIO (build-gpu/,
# Release), the four libraries it loads (libsubsplat, libepoxy, Embree and TBB), the example scene
# files (build/bench/*.ssscene, written by bench/methods.py --export-only), and the GL vendor-neutral
# dispatch libraries (libglvnd) as Debian packages, into .devbuild/ (about 16 MB). The glibc there
# must be 2.36 or newer (Debian 12's).
#   bash scripts/gpu_bundle.sh
set -euo pipefail
cd "$(dirname "$0")/.."
ls build/bench/*.ssscene >/dev/null || { echo "no scene files: run bench/methods.py --export-only (docs/BENCHMARKS.md)"; exit 1; }
cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DSUBSPLAT_BUILD_TESTS=OFF -DSUBSPLAT_WITH_OPENIMAGEIO=OFF >/dev/null
cmake --build build-gpu -j"$(nproc)" --target subsplat_replay
rm -rf .devbuild && mkdir -p .devbuild/lib .devbuild/scenes .devbuild/gl
cp build-gpu/native/subsplat_replay .devbuild/
strip .devbuild/subsplat_replay
for lib in $(ldd build-gpu/native/subsplat_replay | awk '/=> \//{print $3}' | grep -E 'libsubsplat|libepoxy|libembree|libtbb'); do
  cp -L "$lib" .devbuild/lib/
done
strip .devbuild/lib/libsubsplat.so
# Embree alone is 44 MB: the libraries travel as one xz archive (about 10 MB) and are unpacked there.
tar -C .devbuild -cJf .devbuild/lib.tar.xz lib && rm -r .devbuild/lib
cp build/bench/*.ssscene .devbuild/scenes/
mkdir -p /tmp/gpu_bundle_lists/partial
apt="-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/gpu_bundle_lists"
apt-get $apt update >/dev/null
(cd .devbuild/gl && apt-get $apt download libegl1 libglvnd0 libopengl0 libgl1 libglx0 2>/dev/null)
git rev-parse --short HEAD > .devbuild/revision
git diff --quiet HEAD -- native || echo "(with uncommitted changes in native/)" >> .devbuild/revision
du -sh .devbuild
