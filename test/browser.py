"""Headless Chromium from Debian's package, driven by Playwright (no browser download)."""

import shutil
import socket
import tempfile
from contextlib import contextmanager
from pathlib import Path

CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def http_get(url, token=None, timeout=5):
    """(status, body) of a GET, with the viewer's access token if given (errors included; 0
    when nothing answered)."""
    import urllib.error
    import urllib.request

    headers = {"Authorization": f"Bearer {token}"} if token else {}
    try:
        with urllib.request.urlopen(
            urllib.request.Request(url, headers=headers), timeout=timeout
        ) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()
    except OSError as e:  # not up (yet): no status
        return 0, str(e).encode()


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextmanager
def chromium_page(width=1280, height=860, resolve=None, csp=False):
    """A page of a fresh headless Chromium; ``resolve``: host names the browser maps to
    addresses of this machine (a DNS rebinding, without a DNS server). Our pages' CSP forbids
    eval, which Playwright's ``wait_for_function`` and ``evaluate`` use: it is bypassed unless
    ``csp`` (then drive the page with selectors only; ``csp_violations(page)`` lists what the
    policy refused)."""
    from playwright.sync_api import sync_playwright

    exe = shutil.which("chromium")
    assert exe, (
        "Debian's chromium is missing: scripts/test.sh installs it (setup.sh --with-browser)"
    )
    # Chromium's own log, shown when the test fails inside the page. Chromium logs nothing when
    # a renderer dies, even of a SIGSEGV, so each renderer runs under a shell that records how
    # it ended and its stderr: that found why the renderer crashed at a tap in the viewer
    # (killed by SIGTRAP, "V8 javascript OOM": test_browser.tap says why, issue 36).
    folder = Path(tempfile.mkdtemp(prefix="chromium-log-"))
    log = folder / "chrome_debug.log"
    with sync_playwright() as p:
        rules = ", ".join(f"MAP {name} {address}" for name, address in (resolve or {}).items())
        args = CHROMIUM_ARGS + ([f"--host-resolver-rules={rules}"] if rules else [])
        args += ["--enable-logging", f"--log-file={log}", "--v=0"]
        args += [f"--renderer-cmd-prefix={renderer_recorder(folder)}"]
        browser = p.chromium.launch(executable_path=exe, args=args)
        try:
            page = browser.new_page(viewport={"width": width, "height": height}, bypass_csp=not csp)
            page.refused = []
            page.on(
                "console",
                lambda m: (
                    page.refused.append(m.text) if "Content Security Policy" in m.text else None
                ),
            )
            yield page
        except Exception:
            print(chromium_log_tail(log))
            print(renderer_ends(folder))
            raise
        finally:
            browser.close()
            shutil.rmtree(folder, ignore_errors=True)


def chromium_log_tail(log: Path, lines: int = 40) -> str:
    """The end of Chromium's log without its noise (no D-Bus in a test machine)."""
    try:
        text = log.read_text(errors="replace").splitlines()
    except OSError as e:
        return f"----- no Chromium log: {e}"
    kept = [line for line in text if "dbus" not in line and "Floss" not in line]
    return "\n".join([f"----- Chromium's log ({log}, last {lines} lines)", *kept[-lines:]])


def renderer_recorder(folder: Path) -> Path:
    """A shell that runs a renderer, keeps its stderr and appends how it ended (exit status,
    or the signal that killed it) to ``folder/renderers.log``."""
    script = folder / "renderer.sh"
    script.write_text(
        "#!/bin/sh\n"
        f'"$@" 2>>"{folder}/renderers.err"\n'
        "status=$?\n"
        'ended="exit $status"\n'
        '[ "$status" -gt 128 ] && ended="killed by SIG$(kill -l $((status - 128)))"\n'
        f'echo "$(date +%T.%N) renderer $$: $ended" >>"{folder}/renderers.log"\n'
        "exit $status\n"
    )
    script.chmod(0o755)
    return script


def renderer_ends(folder: Path, lines: int = 20) -> str:
    """How each renderer that ended did, and the end of their stderr."""
    parts = []
    for name in ("renderers.log", "renderers.err"):
        try:
            text = (folder / name).read_text(errors="replace").splitlines()
        except OSError:
            text = ["(none)"]
        parts += [f"----- {name} (last {lines} lines)", *text[-lines:]]
    return "\n".join(parts)
