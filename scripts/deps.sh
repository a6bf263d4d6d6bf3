#!/usr/bin/env bash
# Installs what building, testing and the examples need on a fresh Debian machine.
# Only what is missing is installed; safe to run again. Extra packages may be named.
set -euo pipefail
pkgs=(build-essential pkg-config libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri "$@")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "deps: apt-get install ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
command -v cargo >/dev/null || { echo "deps: cargo not found; install Rust (rustup) first" >&2; exit 1; }
