"""The viewer in a real browser (headless Chromium + Playwright): its token and hosts, the graph,
a camera image, a change shown (how soon, printed) and scrubbed back. The clinician's dashboard is
test_browser_dashboard.py."""

import json
import threading
import time
from pathlib import Path

import pytest

from clarc_agents.gug.skeleton import JOINTS, parse_skeleton, skeleton_tx

from browser import chromium_page, free_port, http_get
from ros_processes import (
    agent_in_session,
    send_and_wait,
    snapshot_via,
    wait_for,
)

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "clarc_room.json"


VIEWER_TOKEN = "a-test-token-of-the-viewer"


def http_json(url, token=VIEWER_TOKEN):
    status, body = http_get(url, token)
    if status != 200:
        raise OSError(f"{url}: {status or 'no answer'} {body[:200]!r}")
    return json.loads(body)


def tap(page, node):
    """Tap ``node`` in the viewer's graph, as a click does. The expression returns nothing:
    ``emit`` returns the cytoscape collection, which Playwright would serialise whole (the
    graph, its renderer, its canvases): 2 GB and 9 s in the renderer, and V8's heap limit at the
    second tap ("V8 javascript OOM", the renderer killed: "Target crashed", issue 36)."""
    page.evaluate(f"() => {{ window.dsrViewer.cy.getElementById('n:{node}').emit('tap'); }}")


def spun_while(ros, coroutine):
    """Run ``coroutine`` in an asyncio loop while the test's ROS session spins in a thread (as
    the viewer serves its web app beside its node)."""
    import asyncio
    import threading

    stop = threading.Event()

    def spin():
        while not stop.is_set():
            ros.session.executor.spin_once(timeout_sec=0.05)

    spinner = threading.Thread(target=spin)
    spinner.start()
    try:
        return asyncio.run(coroutine)
    finally:
        stop.set()
        spinner.join(10)


@pytest.fixture
def viewer(ros):
    ros.procs.start_server(ros.tmp / "state", world=WORLD)
    snapshot_via(ros.session, timeout=20)
    port = free_port()
    ros.procs.start(
        "viewer",
        ["dsr_viewer", "--ros-args", "-p", f"port:={port}", "-p", f"token:={VIEWER_TOKEN}"],
    )
    url = f"http://127.0.0.1:{port}/"

    wait_for(lambda: serving(url, seq=0), 20, "the viewer to serve the graph")
    return url


def serving(url, seq=None) -> bool:
    """Whether the viewer at ``url`` serves the graph (at ``seq``, if given)."""
    try:
        current = http_json(url + "api/graph")["seq"]
    except OSError:
        return False
    return seq is None or current == seq


def test_the_viewer_needs_its_token_and_an_allowed_host_and_serves_only_its_files(ros, viewer):
    assert http_get(viewer + "api/graph")[0] == 401
    assert http_get(viewer + "api/graph", "another token")[0] == 401
    for name in ("viewer_app.py", "package.json", "node_modules/cytoscape/package.json"):
        assert http_get(viewer + "static/" + name, VIEWER_TOKEN)[0] == 404, name
    assert http_get(viewer + "static/viewer.js", VIEWER_TOKEN)[0] == 200
    with chromium_page(csp=True) as page:
        answer = page.goto(viewer)  # without the token: nothing
        assert answer.status == 401 and "access token" in page.inner_text("body")
        page.goto(viewer + "?token=" + VIEWER_TOKEN)  # the address printed at start
        page.wait_for_selector("body[data-nodes='14']", timeout=15000)
        assert "token" not in page.url  # it became a cookie, out of the address bar
        assert page.refused == []  # the page works under its own CSP
    rebound = viewer.replace("127.0.0.1", "rebind.example")
    with chromium_page(resolve={"rebind.example": "127.0.0.1"}) as page:
        answer = page.goto(rebound + "?token=" + VIEWER_TOKEN)
        assert answer.status == 403  # DNS rebinding: a wrong Host gets nothing


def test_api_graph_is_the_current_snapshot(ros, viewer):
    doc = http_json(viewer + "api/graph")
    assert doc["format"] == "dsr-graph" and doc["kind"] == "snapshot"
    assert {n["name"] for n in doc["nodes"]} >= {"room", "robot", "kinect", "speaking", "showing"}
    t = http_json(viewer + "api/transform?from=room&to=kinect")
    assert t["translation"] == [2.1, 1.5, 1.2] and t["chain"] == [
        "room",
        "robot",
        "kinect",
    ]


def test_the_inspector_draws_a_camera_image_the_json_never_carries(ros, viewer):
    import numpy as np

    agent = agent_in_session(ros)
    # sensor data goes one hop, writer to viewer: the viewer takes the bytes once it has found
    # this agent's topic (it looks every 0.2 s)
    sensor_topic = f"dsr/sensor_blobs/{ros.session.node.get_name()}"
    wait_for(
        lambda: ros.session.node.count_subscribers(sensor_topic) > 0,
        10,
        "the viewer on this agent's sensor blobs",
        ros.session,
    )
    rgb = np.zeros((480, 640, 3), dtype=np.uint8)
    rgb[100:200, 300:400] = (200, 30, 60)  # a red square
    depth = np.full((480, 640), 2.5, dtype=np.float32)
    op = {"op": "set_node_attrs", "node": "kinect", "attrs": {"cam_rgb": rgb, "cam_depth": depth}}
    assert send_and_wait(ros, agent, {"ops": [op]}).accepted
    summary = {"$binary": "uint8", "shape": [480, 640, 3], "size": rgb.nbytes}
    wait_for(
        lambda: (
            next(n for n in http_json(viewer + "api/graph")["nodes"] if n["name"] == "kinect")[
                "attrs"
            ].get("cam_rgb")
            == summary
        ),
        10,
        "the image in the viewer's graph, by what it is",
    )
    status, body = http_get(viewer + "api/image?node=kinect&attr=cam_rgb", VIEWER_TOKEN)
    assert status == 200 and len(body) == rgb.nbytes
    # bytes the viewer missed (sent before it listened to the agent's topic) come from the
    # agent that wrote them (sensor data: the server never had them), and only as they are
    # under the digest the viewer holds
    from dsr_graph.protocol.blobs import digest_of
    from dsr_graph.ros.blob_service import AsyncBlobClient

    writer = ros.session.node.get_name()
    client = AsyncBlobClient(ros.session.node, timeout=10)
    client.discover()  # (this thread spins the session)
    assert spun_while(ros, client.fetch("kinect", "cam_rgb", digest_of(rgb), writer)) == (
        rgb.tobytes()
    )
    assert spun_while(ros, client.fetch("kinect", "cam_rgb", "sha256:" + "0" * 64, writer)) is None
    missing = AsyncBlobClient(ros.session.node, timeout=10)  # its own, empty, cache
    missing.discover()
    assert spun_while(ros, missing.fetch("kinect", "no_such", digest_of(rgb), writer)) is None
    assert spun_while(ros, missing.fetch("kinect", "cam_rgb", digest_of(rgb))) is None  # server
    # kept by digest: the same digest is the same bytes, asked once
    assert spun_while(ros, client.fetch("kinect", "no_such", digest_of(rgb))) == rgb.tobytes()
    assert http_get(viewer + "api/image?node=kinect&attr=color", VIEWER_TOKEN)[0] == 400
    # a viewer started after the frame holds only its digest: it asks the writer, from its own
    # ROS thread (its executor hangs a client made from the web's thread)
    late = f"http://127.0.0.1:{(port := free_port())}/"
    ros.procs.start(
        "late_viewer",
        ["dsr_viewer", "--ros-args", "-p", f"port:={port}", "-p", f"token:={VIEWER_TOKEN}"],
    )
    wait_for(lambda: serving(late), 20, "the late viewer", ros.session)
    got = {}
    asking = threading.Thread(
        target=lambda: got.update(
            image=http_get(late + "api/image?node=kinect&attr=cam_rgb", VIEWER_TOKEN)
        )
    )
    asking.start()  # while this thread spins the writer, which answers
    ros.session.spin_until(lambda: not asking.is_alive(), 30, "the late viewer's image")
    assert got["image"][0] == 200 and got["image"][1] == rgb.tobytes()
    with chromium_page(csp=True) as page:
        page.goto(viewer + "?token=" + VIEWER_TOKEN)
        page.wait_for_selector("body[data-nodes='14']", timeout=15000)
        tap(page, "kinect")
        page.wait_for_selector("canvas.image[data-attr='cam_rgb'][data-shown]", timeout=5000)
        page.wait_for_selector("canvas.image[data-attr='cam_depth'][data-shown]", timeout=5000)
        pixel = page.evaluate(
            "Array.from(document.querySelector(\"canvas[data-attr='cam_rgb']\")"
            ".getContext('2d').getImageData(350, 150, 1, 1).data)"
        )
        assert pixel == [200, 30, 60, 255]
        assert "<uint8 480x640x3>" in page.inner_text("#node-table")
        assert page.refused == []


def test_viewer_shows_a_change_and_scrubs_back(ros, viewer):
    agent = agent_in_session(ros)
    with chromium_page() as page:
        page.goto(viewer + "?token=" + VIEWER_TOKEN)
        page.wait_for_function("Number(document.body.dataset.nodes) === 14", timeout=15000)
        assert (
            page.evaluate("window.dsrViewer.cy.edges('.rt').length") == 7
        )  # the RT tree, drawn apart
        page.wait_for_timeout(500)  # the live stream is open

        result = send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {"op": "insert_node", "name": "visitor", "type": "person"},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "visitor",
                        "type": "RT",
                        "rt": {"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]},
                    },
                    {"op": "insert_edge", "from": "visitor", "to": "robot", "type": "is_with"},
                ]
            },
        )
        accepted = time.monotonic()
        assert result.accepted
        # how soon is printed, not asserted: a loaded machine may take longer than a second
        page.wait_for_function(
            "window.dsrViewer.cy.getElementById('n:visitor').nonempty()", timeout=10000
        )
        print(
            f"viewer showed the change {1000 * (time.monotonic() - accepted):.0f} ms "
            "after it was accepted"
        )
        assert page.evaluate(
            "window.dsrViewer.cy.getElementById('e:visitor|is_with|robot').nonempty()"
        )
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').hasClass('flash')")

        send_and_wait(
            ros,
            agent,
            {"ops": [{"op": "set_node_attrs", "node": "visitor", "attrs": {"patient": "Carlos"}}]},
        )
        page.wait_for_function("document.body.dataset.seq === '2'", timeout=3000)
        assert page.locator("#deltas li").count() == 2

        # the inspector: attributes, version, pose in another node's frame
        tap(page, "visitor")
        page.wait_for_selector("#node-table")
        table = page.inner_text("#node-table")
        assert "version\t2" in table and "patient\tCarlos" in table
        # who wrote each attribute, and when; who last moved it
        assert "patient\tCarlos\t/test_client, " in table
        assert page.inner_text("#moved").startswith("pose written by /test_client, ")
        page.select_option("#frame", "room")
        page.wait_for_function(
            "document.getElementById('pose').dataset.translation && Math.abs("
            "JSON.parse(document.getElementById('pose').dataset.translation)[0] - 3.0) < 1e-9",
            timeout=3000,
        )
        assert "] m\n" in page.inner_text("#pose")  # the DSR's unit, said

        # scrub back to seq 0: the visitor is not there yet; back to live: it is
        page.locator("#scrub").fill("0")
        page.wait_for_function("document.body.dataset.shownSeq === '0'", timeout=3000)
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').empty()")
        assert "past" in page.inner_text("#status")
        page.click("#deltas li[data-seq='1']")
        page.wait_for_function("document.body.dataset.shownSeq === '1'", timeout=3000)
        assert page.evaluate("window.dsrViewer.cy.getElementById('n:visitor').nonempty()")
        page.click("#live")
        page.wait_for_function(
            "document.body.dataset.live === 'true' && document.body.dataset.shownSeq === '2'",
            timeout=3000,
        )

        # a skeleton frame (Get Up & Go): every joint a geometric node under the person
        skeleton = {
            joint: {"p": [900.0 + 10 * i, 20.0 * (i % 3), -400.0 + 50 * i], "c": 0.9}
            for i, joint in enumerate(JOINTS)
        }
        person = {"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]}
        send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {"op": "insert_node", "name": "person", "type": "person"},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "person",
                        "type": "RT",
                        "rt": person,
                    },
                ]
            },
        )
        send_and_wait(ros, agent, skeleton_tx(agent.graph, parse_skeleton(skeleton), 1.0))
        page.wait_for_function(
            "window.dsrViewer.cy.getElementById('n:person_knee_left').nonempty()", timeout=3000
        )
        rt_edges = page.evaluate("window.dsrViewer.cy.edges('.rt').length")
        assert rt_edges == 9 + len(JOINTS)  # the room's, the visitor, the person, its joints
        tap(page, "person_knee_left")
        page.wait_for_selector("#pose")
        page.select_option("#frame", "kinect")
        page.wait_for_function(  # the knee where the Kinect saw it, in metres (0.1 mm kept)
            "document.getElementById('pose').dataset.translation && Math.abs("
            "JSON.parse(document.getElementById('pose').dataset.translation)[0] - 0.98) < 1e-3",
            timeout=3000,
        )
