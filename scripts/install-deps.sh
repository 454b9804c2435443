#!/usr/bin/env bash
# Installs the Debian packages listed in deps/debian-packages.txt and the npm packages of
# package-lock.json. Idempotent: when everything is already installed it does nothing and needs
# no network.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' "$root/deps/debian-packages.txt" | grep -v '^$')

# A package counts as present when it is installed or provided by an installed one (NodeSource's
# nodejs provides npm, and conflicts with Debian's).
provided="$(dpkg-query -W -f='${Status}|${Provides}\n' 2>/dev/null | grep '^install ok installed|' |
  cut -d'|' -f2 | tr ',' '\n' | sed -e 's/(.*)//' -e 's/[[:space:]]//g' | sort -u)"
missing=()
for pkg in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" && continue
  grep -qx "$pkg" <<<"$provided" && continue
  missing+=("$pkg")
done

if [ "${#missing[@]}" -gt 0 ]; then
  echo "install-deps: installing ${#missing[@]} Debian package(s): ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The npm packages of package.json, exactly as package-lock.json pins them, into node_modules/;
# node_modules/.hribench-lock is the lock they were installed from.
if ! cmp -s "$root/package-lock.json" "$root/node_modules/.hribench-lock"; then
  echo "install-deps: installing the npm packages of package-lock.json"
  (cd "$root" && npm ci --no-audit --no-fund --loglevel=error)
  cp "$root/package-lock.json" "$root/node_modules/.hribench-lock"
fi
