#!/usr/bin/env bash
# Make sure the system packages vkrt needs are present, and install the missing ones.
#
# vkrt needs, at run time, the Vulkan loader and a Vulkan driver, and at build time glslang
# (GLSL -> SPIR-V) and spirv-tools (spirv-val, used by the tests). On a machine with no GPU the
# driver is Mesa's lavapipe. We want Mesa 25 from Debian's bookworm-backports suite rather than
# Debian 12's stock Mesa 22.3: it ran our ray-triangle kernel 12x faster (306 vs 26 M tests/s).
#
# Usage: tools/ensure-deps.sh [--with-validation] [--with-slurm] [--with-swiftshader] [--with-python]
#   --with-validation  also install the Khronos validation layers (the tests turn them on when present)
#   --with-slurm       also install Slurm and MUNGE (slurm-wlm, munge): tests/slurm.rs starts a
#                      one-node cluster of its own with them (no systemd services are used)
#   --with-swiftshader also unpack SwiftShader, a second CPU Vulkan implementation, from Debian's
#                      chromium-common package (downloaded, not installed: no Chromium) into
#                      /opt/vkrt-swiftshader, with an ICD file there that names it; it stays
#                      invisible until VK_ADD_DRIVER_FILES=/opt/vkrt-swiftshader/vk_swiftshader_icd.json
#   --with-python      also install Python 3 with venv (python3, python3-venv): the Python
#                      package's tests (tools/python-test) build and install it in a virtual
#                      environment of their own
#
# Prints what it installs; prints nothing more than one line when everything is already there.
set -euo pipefail
# dpkg needs ldconfig and friends from the sbin folders, which a non-login PATH (CI's) may lack.
export PATH="$PATH:/usr/local/sbin:/usr/sbin:/sbin"

want_validation=0
want_slurm=0
want_swiftshader=0
want_python=0
for arg in "$@"; do
  case "$arg" in
    --with-validation) want_validation=1 ;;
    --with-slurm) want_slurm=1 ;;
    --with-swiftshader) want_swiftshader=1 ;;
    --with-python) want_python=1 ;;
    -h|--help) awk 'NR == 1 { next } /^#/ { sub(/^# ?/, ""); print; next } { exit }' "$0"; exit 0 ;;
    *) echo "ensure-deps: unknown argument '$arg'" >&2; exit 2 ;;
  esac
done

# The lowest Mesa major version we accept for lavapipe (see above).
MIN_MESA_MAJOR=25

have_cmd() { command -v "$1" >/dev/null 2>&1; }
have_loader() { ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1'; }
mesa_major() {
  dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null | sed -E 's/^([0-9]+:)?([0-9]+).*/\2/' || true
}
have_lavapipe() {
  local major
  major=$(mesa_major)
  [ -n "$major" ] && [ "$major" -ge "$MIN_MESA_MAJOR" ] && ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1
}
have_validation() { ls /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >/dev/null 2>&1; }

missing=()
have_cmd glslangValidator || missing+=(glslang-tools)
have_cmd spirv-val || missing+=(spirv-tools)
have_loader || missing+=(libvulkan1)
need_mesa=0
have_lavapipe || need_mesa=1
if [ "$want_validation" = 1 ] && ! have_validation; then missing+=(vulkan-validationlayers); fi
if [ "$want_slurm" = 1 ]; then
  { have_cmd sbatch && have_cmd slurmctld && have_cmd slurmd; } || missing+=(slurm-wlm)
  { have_cmd munged && have_cmd mungekey; } || missing+=(munge)
fi
if [ "$want_python" = 1 ]; then
  have_cmd python3 || missing+=(python3)
  # Debian splits venv's pip bootstrap out of python3 itself.
  python3 -c 'import ensurepip, venv' >/dev/null 2>&1 || missing+=(python3-venv)
fi

# SwiftShader (--with-swiftshader): Chromium's Vulkan implementation, from Debian's
# chromium-common package, unpacked beside nothing else. Its ICD file's library_path is made
# absolute, so VK_ADD_DRIVER_FILES can name it from anywhere.
SWIFTSHADER_DIR=/opt/vkrt-swiftshader
ensure_swiftshader() {
  [ "$want_swiftshader" = 1 ] || return 0
  local icd="$SWIFTSHADER_DIR/vk_swiftshader_icd.json"
  if [ -f "$icd" ] && [ -f "$SWIFTSHADER_DIR/libvk_swiftshader.so" ]; then
    echo "ensure-deps: SwiftShader is unpacked ($icd)"
    return 0
  fi
  local sudo="" tmp
  if [ "$(id -u)" != 0 ]; then
    if have_cmd sudo && sudo -n true 2>/dev/null; then sudo="sudo -n"; else
      echo "ensure-deps: need root to unpack SwiftShader into $SWIFTSHADER_DIR; run this script as root" >&2
      return 1
    fi
  fi
  tmp=$(mktemp -d)
  echo "ensure-deps: unpacking SwiftShader from Debian's chromium-common into $SWIFTSHADER_DIR"
  (cd "$tmp" && { apt-get download -qq chromium-common 2>/dev/null || { $sudo apt-get update -qq && apt-get download -qq chromium-common; }; }) >/dev/null
  dpkg-deb -x "$tmp"/chromium-common_*.deb "$tmp/x"
  $sudo mkdir -p "$SWIFTSHADER_DIR"
  $sudo cp "$tmp/x/usr/lib/chromium/libvk_swiftshader.so" "$SWIFTSHADER_DIR/"
  sed 's|"library_path": *"[^"]*"|"library_path": "'"$SWIFTSHADER_DIR"'/libvk_swiftshader.so"|' \
    "$tmp/x/usr/lib/chromium/vk_swiftshader_icd.json" | $sudo tee "$icd" >/dev/null
  rm -rf "$tmp"
  grep -q "$SWIFTSHADER_DIR/libvk_swiftshader.so" "$icd" || { echo "ensure-deps: SwiftShader's ICD file was not written" >&2; return 1; }
}

if [ ${#missing[@]} -eq 0 ] && [ "$need_mesa" = 0 ]; then
  echo "ensure-deps: Vulkan loader, Mesa $(mesa_major) lavapipe and glslang are present$( [ $want_slurm = 1 ] && echo ", and Slurm and MUNGE" )"
  ensure_swiftshader
  exit 0
fi

if ! have_cmd apt-get; then
  echo "ensure-deps: missing ${missing[*]} $( [ $need_mesa = 1 ] && echo "mesa-vulkan-drivers>=$MIN_MESA_MAJOR" ) and this is not a Debian system; install them by hand" >&2
  exit 1
fi

SUDO=""
if [ "$(id -u)" != 0 ]; then
  if have_cmd sudo && sudo -n true 2>/dev/null; then SUDO="sudo -n"; else
    echo "ensure-deps: need root to install: ${missing[*]} mesa-vulkan-drivers (bookworm-backports); run this script as root" >&2
    exit 1
  fi
fi

export DEBIAN_FRONTEND=noninteractive
if [ "$need_mesa" = 1 ]; then
  # Add bookworm-backports with the same mirror the machine already uses for Debian itself.
  if ! grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    uri=$(grep -hsE '^URIs:' /etc/apt/sources.list.d/*.sources | grep -v security | awk '{print $2}' | grep -m1 debian || true)
    [ -n "$uri" ] || uri=$(grep -hsE '^deb ' /etc/apt/sources.list | grep -v security | awk '{print $2}' | grep -m1 debian || true)
    [ -n "$uri" ] || uri=http://deb.debian.org/debian
    echo "ensure-deps: adding bookworm-backports from $uri"
    printf 'Types: deb\nURIs: %s\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' "$uri" \
      | $SUDO tee /etc/apt/sources.list.d/vkrt-bookworm-backports.sources >/dev/null
  fi
fi

echo "ensure-deps: installing ${missing[*]} $( [ $need_mesa = 1 ] && echo "mesa-vulkan-drivers (bookworm-backports)" )"
$SUDO apt-get update -qq
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [ "$need_mesa" = 1 ]; then
  $SUDO apt-get install -y -qq --no-install-recommends -t bookworm-backports mesa-vulkan-drivers >/dev/null
fi
have_lavapipe || { echo "ensure-deps: mesa-vulkan-drivers >= $MIN_MESA_MAJOR did not install" >&2; exit 1; }
echo "ensure-deps: done (Mesa $(mesa_major) lavapipe, $(glslangValidator --version 2>/dev/null | head -1))"
ensure_swiftshader
