# Sourced by validation/*/run.sh: installs Debian's python3-matplotlib and python3-numpy with
# apt-get when Debian's /usr/bin/python3 ($PY) cannot import them.
if ! "$PY" -c 'import matplotlib, numpy' 2>/dev/null; then
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO=sudo
    $SUDO apt-get update
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
        python3-matplotlib python3-numpy
fi
