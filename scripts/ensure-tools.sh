#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Make sure a simulator/linter binary is on PATH: install it with apt-get when running as root,
# otherwise stop with a message saying what to install.  Usage: ensure-tools.sh iverilog [verilator]
set -euo pipefail
missing=()
for tool in "$@"; do
  command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "Installing ${missing[*]} with apt-get ..."
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # Debian package of each tool (vvp comes with iverilog)
  packages=()
  for tool in "${missing[@]}"; do
    case "$tool" in vvp) packages+=(iverilog) ;; *) packages+=("$tool") ;; esac
  done
  apt-get install -y -qq "${packages[@]}" >/dev/null
  for tool in "${missing[@]}"; do
    command -v "$tool" >/dev/null 2>&1 || { echo "error: apt-get did not provide $tool" >&2; exit 1; }
  done
else
  echo "error: ${missing[*]} not found on PATH." >&2
  echo "Install it first, e.g.: sudo apt-get install ${missing[*]}" >&2
  echo "(make installs it by itself when run as root)" >&2
  exit 1
fi
