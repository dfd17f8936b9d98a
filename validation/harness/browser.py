"""Headless Chromium (Debian package `chromium`) for the report checks: load a page,
read back the DOM after scripts ran, take screenshots. No network is touched."""
import shutil
import subprocess
import tempfile

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--virtual-time-budget=10000"]


def chromium():
    return shutil.which("chromium") or shutil.which("chromium-browser")


def _run(args, timeout=120):
    exe = chromium()
    if not exe:
        raise RuntimeError("chromium is not installed (apt-get install chromium)")
    with tempfile.TemporaryDirectory() as profile:
        return subprocess.run([exe, *FLAGS, f"--user-data-dir={profile}", *args], capture_output=True, text=True,
                              timeout=timeout)


def dump_dom(path):
    return _run(["--dump-dom", f"file://{path}"]).stdout


def screenshot(path, png, width=1280, height=1600):
    _run([f"--window-size={width},{height}", f"--screenshot={png}", f"file://{path}"])
    return png
