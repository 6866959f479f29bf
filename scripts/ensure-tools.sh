#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Make sure a simulator/linter binary is on PATH: install it with apt-get when running as root,
# otherwise stop with a message saying what to install.  Tools named after --optional only
# speed things up (ccache: Verilator's compiles): without root they are left out with a note.
# Usage: ensure-tools.sh iverilog [verilator ...] [--optional ccache ...]
set -euo pipefail
missing=()
optional=()
kind=required
for tool in "$@"; do
  if [ "$tool" = "--optional" ]; then kind=optional; continue; fi
  command -v "$tool" >/dev/null 2>&1 && continue
  if [ "$kind" = required ]; then missing+=("$tool"); else optional+=("$tool"); fi
done
[ ${#missing[@]} -eq 0 ] && [ ${#optional[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
  export DEBIAN_FRONTEND=noninteractive
  if [ ${#missing[@]} -gt 0 ]; then
    echo "Installing ${missing[*]} with apt-get ..."
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
  fi
  for tool in "${optional[@]}"; do
    echo "Installing $tool with apt-get ..."
    apt-get install -y -qq "$tool" >/dev/null 2>&1 \
      || { apt-get update -qq >/dev/null 2>&1 || true; apt-get install -y -qq "$tool" >/dev/null 2>&1; } \
      || echo "note: apt-get could not install $tool: builds run without it"
  done
elif [ ${#missing[@]} -eq 0 ]; then
  echo "note: ${optional[*]} not found on PATH: builds run without it (sudo apt-get install ${optional[*]})"
else
  echo "error: ${missing[*]} not found on PATH." >&2
  echo "Install it first, e.g.: sudo apt-get install ${missing[*]}" >&2
  echo "(make installs it by itself when run as root)" >&2
  exit 1
fi
