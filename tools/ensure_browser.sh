#!/usr/bin/env bash
# Make Debian's headless Chromium (and its WebDriver) available for the browser test
# (tests/test_browser.py, marked `browser`).  Idempotent and best effort: it installs only
# when something is missing and we are root with apt-get; otherwise it prints a note and
# exits 0, and the browser test skips with a clear reason.
#
# The browser comes from Debian's packages (chromium, chromium-driver), never from a
# download by Playwright or Selenium Manager.
set -u

have_all() { [ -x /usr/bin/chromium ] && [ -x /usr/bin/chromedriver ]; }

if have_all; then
    echo "ensure_browser: /usr/bin/chromium and /usr/bin/chromedriver present"
    exit 0
fi
if [ "$(id -u)" != "0" ] || ! command -v apt-get >/dev/null 2>&1; then
    echo "ensure_browser: chromium or chromedriver missing and not root with apt-get;" \
         "install Debian's 'chromium' and 'chromium-driver' packages to run the browser test" \
         "(it is skipped without them)"
    exit 0
fi
echo "ensure_browser: installing Debian's chromium and chromium-driver (apt-get)"
export DEBIAN_FRONTEND=noninteractive
if apt-get update -qq && apt-get install -y -qq --no-install-recommends \
        chromium chromium-driver fonts-dejavu-core >/dev/null; then
    echo "ensure_browser: installed $(/usr/bin/chromium --version 2>/dev/null || echo chromium)"
else
    echo "ensure_browser: apt-get failed; the browser test will be skipped"
fi
exit 0
