#!/usr/bin/env bash
# System packages the build needs: OpenBLAS (shared, with LAPACK) for clarabel's
# semidefinite cones (the robid-sdp crate with its `clarabel` feature, which robots' and
# tests' `sdp` features turn on; docs/experiments.md#semidefinite-program).
# Idempotent: installs only what is missing; does nothing when all is present.
set -euo pipefail

packages=(libopenblas-dev)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "install-deps: ${packages[*]} already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
