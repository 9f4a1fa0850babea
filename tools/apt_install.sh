# Sourced by setup.sh and validation/plot_deps.sh: apt_install WHO PACKAGE... installs the
# packages with apt-get (update, then install without recommendations, non-interactive), through
# sudo when not root. Another apt-get holding its lock (at boot, apt-daily's update holds the
# lists' lock, which DPkg::Lock::Timeout does not cover; helper 156) is waited for, trying again
# every 10 s for up to 10 minutes. Returns 1 after one line on stderr, prefixed "WHO: ", where
# installing needs root and there is no sudo, or where apt-get fails (its errors above it).

# apt-get "$@" as $_apt_sudo, retried while another apt-get holds its lock, until 10 minutes
# have passed (apt-get's own wait for dpkg's lock counts). In English (LC_ALL=C), whose words
# tell a held lock.
_apt_get() {
  local log rc start=$SECONDS
  log=$(mktemp)
  while :; do
    rc=0
    $_apt_sudo env DEBIAN_FRONTEND=noninteractive LC_ALL=C apt-get -o DPkg::Lock::Timeout=600 \
      "$@" 2> >(tee "$log" >&2) || rc=$?
    wait  # (for tee: no job of the caller runs meanwhile)
    if [ "$rc" -ne 0 ] && grep -q "Could not get lock" "$log" && ((SECONDS - start < 600)); then
      echo "$_apt_who: another apt-get holds its lock; trying again in 10 s" >&2
      sleep 10
      continue
    fi
    rm -f "$log"
    return "$rc"
  done
}

apt_install() {
  _apt_who=$1
  shift
  _apt_sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null; then
      echo "$_apt_who: these packages are missing and installing them needs root: $*;" \
           "run as root, or install sudo" >&2
      return 1
    fi
    _apt_sudo="sudo"
  fi
  echo "$_apt_who: installing $*" >&2
  if ! _apt_get update; then
    echo "$_apt_who: apt-get update failed (its errors are above)" >&2
    return 1
  fi
  if ! _apt_get install -y --no-install-recommends "$@"; then
    echo "$_apt_who: apt-get install failed (its errors are above); a package it cannot locate" \
         "means the update above did not reach Debian's package archive" >&2
    return 1
  fi
}
