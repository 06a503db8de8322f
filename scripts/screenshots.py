"""Photographs the DSR viewer and the clinician's dashboard during a real run
(see screenshots.sh)."""

import os
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "test"))
from browser import chromium_page, free_port  # noqa: E402  (the browser tests' own helper)

OUT = ROOT / "docs" / "images"


PASSWORD = "screenshots only, a long passphrase"
TOKEN = "screenshots-token"


def wait_http(url: str, seconds: float) -> None:
    deadline = time.monotonic() + seconds
    while True:
        try:
            urllib.request.urlopen(url, timeout=2).read()
            return
        except urllib.error.HTTPError:
            return  # it answers (a 401 before logging in)
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.3)


def main() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    viewer_port, dashboard_port = free_port(), free_port()
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run(
            ["clarc", "user", "add", "Dr. Ruiz", "--role", "clinician", "--db", f"{tmp}/db.sqlite"],
            input=f"{PASSWORD}\n{PASSWORD}\n",
            text=True,
            check=True,
        )
        launch = subprocess.Popen(
            [
                str(ROOT / "scripts" / "launch.sh"),
                "--wait-start",
                "--db",
                f"{tmp}/db.sqlite",
                "--run-dir",
                f"{tmp}/run",
                "--viewer-port",
                str(viewer_port),
                "--dashboard-port",
                str(dashboard_port),
                "--scale",
                "0.3",
                "--viewer-token",
                TOKEN,
            ],
            stdout=subprocess.DEVNULL,
            env=dict(os.environ),
        )
        try:
            dashboard, viewer = (
                f"http://127.0.0.1:{dashboard_port}/",
                f"http://127.0.0.1:{viewer_port}/",
            )
            wait_http(dashboard + "login", 60)
            wait_http(viewer + "api/graph", 60)
            with chromium_page(1280, 860) as page:
                page.goto(dashboard + "login")
                page.fill("#name", "Dr. Ruiz")
                page.fill("#password", PASSWORD)
                page.click("#log-in")
                page.wait_for_selector("body[data-ready=true]")
                page.fill("#new-patient", "Carlos")  # the scenario's patient, as a record
                page.click("#add-patient")
                page.wait_for_function("document.getElementById('patient-id').value !== ''")
                page.select_option("#test", "barthel")  # the scenario's test
                page.click("#start")
                page.wait_for_function(
                    "document.getElementById('live-item').textContent.includes('3/10')",
                    timeout=60000,
                )
                view = page.context.browser.new_page(viewport={"width": 1280, "height": 860})
                view.goto(viewer + "?token=" + TOKEN)
                view.wait_for_function("Number(document.body.dataset.nodes) > 20", timeout=20000)
                view.wait_for_timeout(1500)
                view.evaluate("window.dsrViewer.cy.getElementById('n:person').emit('tap')")
                view.wait_for_timeout(800)
                view.screenshot(path=str(OUT / "viewer.png"))
                page.wait_for_selector("body[data-running=false]", timeout=180000)
                page.wait_for_function("Number(document.body.dataset.results) >= 1", timeout=10000)
                page.click("#results tbody tr")
                page.wait_for_timeout(300)
                page.screenshot(path=str(OUT / "dashboard.png"), full_page=True)
        finally:
            launch.terminate()
            launch.wait(timeout=30)
    print(f"wrote {OUT / 'viewer.png'} and {OUT / 'dashboard.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
