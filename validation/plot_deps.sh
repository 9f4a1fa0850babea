# Sourced by validation/*/run.sh: installs Debian's python3-matplotlib and python3-numpy with
# apt-get when Debian's /usr/bin/python3 ($PY) cannot import them (one line and exit 1 where that
# needs root and there is no sudo, or apt-get fails).
if ! "$PY" -c 'import matplotlib, numpy' 2>/dev/null; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then
        if ! command -v sudo >/dev/null; then
            echo "$0: python3-matplotlib and python3-numpy are missing and installing them needs" \
                 "root: run as root, or install sudo" >&2
            exit 1
        fi
        SUDO=sudo
    fi
    if ! $SUDO apt-get update ||
        ! $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
            python3-matplotlib python3-numpy; then
        echo "$0: installing python3-matplotlib and python3-numpy failed (the errors are above)" >&2
        exit 1
    fi
fi
