"""A small WebDriver client (the W3C protocol, over chromedriver's HTTP API,
with urllib only): enough to drive headless Chromium for the playground's
browser tests. Nothing here is downloaded; chromedriver and chromium are the
Debian packages that scripts/setup installs."""

import base64
import json
import os
import socket
import subprocess
import tempfile
import time
import urllib.error
import urllib.request

# The flags the brief requires: without the background-networking ones the
# browser's own connections are refused on this machine.
CHROMIUM_ARGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    "--allow-file-access-from-files", "--window-size=1500,1300",
]


class WebDriverError(Exception):
    pass


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Browser:
    """One chromedriver process and one headless Chromium session."""

    def __init__(self, chromium="chromium", chromedriver="chromedriver"):
        self.port = _free_port()
        self.profile = tempfile.mkdtemp(prefix="jsref-chromium-")
        self.log = open(os.path.join(self.profile, "chromedriver.log"), "w")
        self.driver = subprocess.Popen([chromedriver, "--port=%d" % self.port],
                                       stdout=self.log, stderr=subprocess.STDOUT)
        self.base = "http://127.0.0.1:%d" % self.port
        deadline = time.time() + 20
        while True:
            try:
                self._request("GET", "/status")
                break
            except (urllib.error.URLError, ConnectionError, WebDriverError):
                if time.time() > deadline:
                    self.driver.kill()
                    raise WebDriverError("chromedriver did not start")
                time.sleep(0.1)
        binary = subprocess.run(["readlink", "-f", _which(chromium)], capture_output=True, text=True).stdout.strip()
        caps = {"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {"binary": _chromium_binary(binary),
                                   "args": CHROMIUM_ARGS + ["--user-data-dir=" + os.path.join(self.profile, "user")]},
            "goog:loggingPrefs": {"browser": "ALL"},
        }}}
        r = self._request("POST", "/session", caps)
        self.session = r["sessionId"] if "sessionId" in r else r["value"]["sessionId"]

    def _request(self, method, path, body=None):
        data = json.dumps(body).encode() if body is not None else None
        req = urllib.request.Request(self.base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(req, timeout=120) as resp:
                payload = json.loads(resp.read().decode() or "{}")
        except urllib.error.HTTPError as e:
            try:
                payload = json.loads(e.read().decode())
                msg = payload.get("value", {}).get("message", str(e))
            except Exception:
                msg = str(e)
            raise WebDriverError(msg.split("\n")[0])
        return payload

    def _s(self, method, path, body=None):
        return self._request(method, "/session/%s%s" % (self.session, path), body).get("value")

    def get(self, url):
        self._s("POST", "/url", {"url": url})

    def js(self, script, *args):
        """Runs [script] (a function body; [arguments] are the args) and returns its value."""
        return self._s("POST", "/execute/sync", {"script": script, "args": list(args)})

    def screenshot(self, path):
        png = base64.b64decode(self._s("GET", "/screenshot"))
        with open(path, "wb") as f:
            f.write(png)

    def set_size(self, width, height):
        self._s("POST", "/window/rect", {"width": width, "height": height})

    def browser_log(self):
        try:
            return self._s("POST", "/se/log", {"type": "browser"}) or []
        except WebDriverError:
            return []

    def close(self):
        try:
            self._request("DELETE", "/session/%s" % self.session)
        except Exception:
            pass
        self.driver.terminate()
        try:
            self.driver.wait(10)
        except subprocess.TimeoutExpired:
            self.driver.kill()
        self.log.close()


def _which(name):
    for d in os.environ.get("PATH", "").split(os.pathsep):
        p = os.path.join(d, name)
        if os.access(p, os.X_OK):
            return p
    return name


def _chromium_binary(path):
    # Debian's /usr/bin/chromium is a shell wrapper; chromedriver wants the ELF.
    for p in ("/usr/lib/chromium/chromium", path):
        if os.access(p, os.X_OK):
            return p
    return path
