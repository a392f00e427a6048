#!/usr/bin/env bash
# Installs the Debian 12 packages moire needs that are not installed yet. As root it runs
# apt-get; otherwise it prints the apt-get line to run and exits with status 1.
#   scripts/deps.sh --list   prints the package list, one a line, and installs nothing.
# This list is the only one: tests/deps/check-deps.sh reads it through --list and fails when the
# configured build, its tests or its benchmarks use a file of a package it does not bring in.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  llvm-16-dev libzstd-dev        # the JIT backend (LLVM's CMake package needs zstd)
  re2c                           # the lexer generator
  libopenimageio-dev             # image output
  zlib1g-dev                     # deflate for the banded PNG encoder (runtime/output/PngBands)
  glslang-dev glslang-tools spirv-tools  # the GPU backend: GLSL -> SPIR-V, spirv-val (glslang's CMake package names glslangValidator)
  libvulkan-dev                  # the Vulkan loader and headers
  mesa-vulkan-drivers            # lavapipe: a software Vulkan device where there is no GPU
  vulkan-tools                   # vulkaninfo: the devices test compares `moire devices` with it
  libfmt-dev libcli11-dev        # formatting, the command line
  nlohmann-json3-dev             # moire check --format=json
  doctest-dev                    # the tests
  ffmpeg                         # clips to mp4, webm and gif (moire clip)
  libglfw3-dev libgl-dev libgl1-mesa-dri  # the viewer (moire view): a window, OpenGL 2.1
  xvfb xauth xdotool             # the viewer's tests: a virtual X server, and input for it
  clang-16 libclang-rt-16-dev    # the libFuzzer build of fuzz/ (libFuzzer, ASan, UBSan runtimes)
  clang-format-16                # CI's format check (scripts/check-format.sh): the toolchain's version
  nodejs npm                     # the editor packages (npm ci, tsc, vsce) and moire lsp's scripted session (node --test)
  vim                            # the editor packages' tests: the Vim package loaded in batch mode
  libimgui-dev                   # the viewer's parameter panel (Dear ImGui over GLFW and OpenGL 2)
  libcpp-httplib-dev             # moire serve: the preview page's HTTP server
  chromium                       # the browser tests of moire serve's and moire export's pages
  slurm-wlm munge                # moire farm's test: a one-node Slurm cluster (tests/farm)
  libcairo2-dev                  # experiments/explicit_geometry: a real path renderer to compare with (spec §9.5)
)

if [[ "${1:-}" == "--list" ]]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

# Installed, or provided by an installed package: a Node.js from outside Debian (NodeSource's)
# provides npm, and conflicts with Debian's, which apt would otherwise put in its place.
present() {
  local status
  status=$(dpkg-query -W -f='${db:Status-Status}' "$1" 2>/dev/null || true)
  [[ "$status" == "installed" ]] ||
    grep -qE "^installed (.*[ ,])?$1( \(|,|$)" <<<"$provided"
}
provided=$(dpkg-query -W -f='${db:Status-Status} ${Provides}\n' 2>/dev/null || true)

missing=()
for p in "${packages[@]}"; do
  present "$p" || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

line="apt-get install -y --no-install-recommends ${missing[*]}"
if [[ $(id -u) -ne 0 ]]; then
  echo "moire needs these Debian packages; install them with:" >&2
  echo "  sudo apt-get update && sudo $line" >&2
  exit 1
fi
echo "Installing: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
$line
