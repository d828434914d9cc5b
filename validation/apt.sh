# Sourced by the validation scripts: `apt_install PACKAGE` installs one Debian package when apt
# is there and we are root (CI's case), quietly; it returns 1, installing nothing, otherwise, so
# that the caller decides how loudly to skip.
apt_install() {
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    echo "installing $1 with apt"
    apt-get update -qq >/dev/null
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$1" >/dev/null
  else
    return 1
  fi
}
