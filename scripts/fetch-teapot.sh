#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Fetch the Utah teapot's Bezier patches (28 bicubic patches, "BBP" format) into data/teapot.bez.
# The data comes from Debian's geomview package (/usr/share/geomview/geom/teapot.bez); only that
# one file is extracted from the .deb, nothing is installed.  Usage: scripts/fetch-teapot.sh [dest]
set -euo pipefail
dest="${1:-$(cd "$(dirname "$0")/.." && pwd)/data/teapot.bez}"
member="usr/share/geomview/geom/teapot.bez"
[ -s "$dest" ] && exit 0

fail() {
  echo "error: cannot fetch the teapot patches: $*" >&2
  echo "Get Debian's geomview package by hand and copy /$member to $dest, e.g.:" >&2
  echo "  apt-get download geomview && dpkg-deb -x geomview_*.deb x && cp x/$member $dest" >&2
  exit 1
}

command -v apt-get >/dev/null 2>&1 || fail "apt-get not found (a Debian/Ubuntu system is needed)"
command -v dpkg-deb >/dev/null 2>&1 || fail "dpkg-deb not found"

if ! apt-cache show geomview >/dev/null 2>&1; then
  if [ "$(id -u)" -eq 0 ]; then
    echo "apt package lists do not know geomview; running apt-get update ..."
    apt-get update -qq || fail "apt-get update failed"
  else
    fail "the apt package lists do not know geomview (run 'sudo apt-get update' first)"
  fi
fi

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# As root apt drops to the _apt user to download, which cannot write into the private temp dir.
sandbox=()
[ "$(id -u)" -eq 0 ] && sandbox=(-o APT::Sandbox::User=root)
echo "Downloading Debian's geomview package for the teapot patches ..."
(cd "$tmp" && apt-get download -qq "${sandbox[@]}" geomview >/dev/null) || fail "apt-get download geomview failed"
deb="$(ls "$tmp"/geomview_*.deb 2>/dev/null | head -n 1)"
[ -n "$deb" ] || fail "apt-get download produced no geomview_*.deb"
dpkg-deb -x "$deb" "$tmp/x" || fail "dpkg-deb -x $deb failed"
[ -s "$tmp/x/$member" ] || fail "$member is not in $(basename "$deb")"
mkdir -p "$(dirname "$dest")"
cp "$tmp/x/$member" "$dest.tmp"
mv "$dest.tmp" "$dest"
echo "wrote $dest ($(grep -c . "$dest") non-empty lines, from $(basename "$deb"))"
