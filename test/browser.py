"""Headless Chromium from Debian's package, driven by Playwright (no browser download)."""

import shutil
import socket
from contextlib import contextmanager

CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextmanager
def chromium_page(width=1280, height=860):
    from playwright.sync_api import sync_playwright

    exe = shutil.which("chromium")
    assert exe, (
        "Debian's chromium is missing: scripts/test.sh installs it (setup.sh --with-browser)"
    )
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS)
        try:
            yield browser.new_page(viewport={"width": width, "height": height})
        finally:
            browser.close()
