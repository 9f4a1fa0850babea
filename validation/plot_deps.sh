# Sourced by validation/*/run.sh (from any directory): installs Debian's python3-matplotlib
# and python3-numpy (tools/apt_install.sh) when Debian's /usr/bin/python3 ($PY) cannot import
# them; exits 1 with one line where it cannot.
if ! "$PY" -c 'import matplotlib, numpy' 2>/dev/null; then
    source "$(dirname "${BASH_SOURCE[0]}")/../tools/apt_install.sh"
    apt_install "$0" python3-matplotlib python3-numpy || exit 1
fi
