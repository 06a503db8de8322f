"""Recording to MCAP: a Barthel run recorded by scripts/launch.sh --record opens with the mcap
library, holds the DSR and the ROS topics, rebuilds the server's graph at the end, and replays
in the viewer; a recorder killed outright leaves a file readable up to its last flush."""

import json
import os
import subprocess
import time
from pathlib import Path

import pytest

from browser import chromium_page, free_port, http_get
from ros_processes import wait_for

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "clarc_room.json"
TOPICS = {
    "/dsr/snapshot",
    "/dsr/deltas",
    "/tf",
    "/tf_static",
    "/dsr/markers",
    "/clarc/kinect/person",
    "/clarc/asr",
    "/clarc/speaker/say",
    "/clarc/speaker/events",
    "/clarc/panel/display",
    "/clarc/panel/tap",
    "/humans/persons/tracked",
    "/humans/voices/tracked",
    "/humans/voices/anonymous_speaker/speech",
}


def server_graph_at_end(state_dir: Path) -> dict:
    """The server's graph as its state directory holds it: snapshot plus journal."""
    from dsr_graph.formats import dsr_json
    from dsr_graph.formats.state_store import StateStore
    from dsr_graph.model.provenance import apply_delta

    store = StateStore(state_dir)
    snapshot = store.load_snapshot()
    graph, seq = dsr_json.snapshot_from_json(snapshot)
    last = [seq]

    def replay(delta):  # as the server replays it: who wrote each value, and when, included
        apply_delta(graph, delta)
        last[0] = delta["seq"]

    store.replay_journal(seq, replay)
    return json.loads(json.dumps(dsr_json.to_json(graph, "snapshot", seq=last[0])))


@pytest.fixture
def recorded_run(default_run):
    """The default scenario's launch, recorded (conftest.py: the Barthel scenarios' run too)."""
    tmp, run = default_run
    assert "[launch] recorded " in run.stdout and str(tmp / "run.mcap") in run.stdout
    return tmp


def test_the_recording_opens_with_the_mcap_library_and_holds_the_topics(recorded_run):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    with open(recorded_run / "run.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        counts = summary.statistics.channel_message_counts
        by_topic = {c.topic: counts.get(c.id, 0) for c in summary.channels.values()}
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        missing = {t for t in TOPICS if not by_topic.get(t)}
        assert not missing, f"nothing recorded on {missing}: {by_topic}"
        # every message decodes with the schema stored in the file
        for _schema, channel, _message, decoded in reader.iter_decoded_messages(
            topics=["/tf_static", "/dsr/markers"]
        ):
            if channel.topic == "/tf_static":
                assert decoded.transforms and decoded.transforms[0].header.frame_id
            else:
                assert decoded.markers


def test_what_the_patient_said_is_on_rep_155_s_voice_topic_as_the_asr_heard_it(recorded_run):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory

    heard, said = [], []
    with open(recorded_run / "run.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        topics = ["/clarc/asr", "/humans/voices/anonymous_speaker/speech"]
        for _, channel, _, m in reader.iter_decoded_messages(topics=topics):
            if channel.topic == "/clarc/asr":
                heard.append(json.loads(m.data)["text"])
            else:
                assert m.locale == "en_US" and m.confidence == 1.0 and not m.incremental
                said.append(m.final)
    assert heard and said == heard


def test_the_recording_rebuilds_the_server_graph_at_the_end(recorded_run):
    from dsr_graph.formats import dsr_json
    from dsr_graph.protocol.replay import replay_history

    history = replay_history(recorded_run / "run.mcap")
    rebuilt = json.loads(json.dumps(dsr_json.to_json(history.graph, "snapshot", seq=history.seq)))
    expected = server_graph_at_end(recorded_run / "run" / "dsr_state")
    assert rebuilt["seq"] == expected["seq"] > 100
    assert rebuilt == expected
    assert history.first_seq == 0  # recording began at the world as loaded
    start = history.graph_at(0)
    assert "person" not in start and "person" in history.graph


def test_the_recording_replays_in_the_viewer(recorded_run, tmp_path):
    port = free_port()
    url = f"http://127.0.0.1:{port}/"
    viewer = subprocess.Popen(
        [
            *("dsr", "view", "--replay", str(recorded_run / "run.mcap")),
            *("--port", str(port), "--token", "replay-token"),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:

        def up():
            status, body = http_get(url + "api/info", "replay-token")
            return status == 200 and json.loads(body)["replay"] == "run.mcap"

        wait_for(up, 30, "the replay viewer to serve")
        assert http_get(url + "api/graph")[0] == 401  # a recording is patients' data too
        end = json.loads(http_get(url + "api/graph", "replay-token")[1])
        with chromium_page() as page:
            page.goto(url + "?token=replay-token")
            # a recording opens at its start, on the timeline from its first seq to its last
            page.wait_for_function("document.body.dataset.shownSeq === '0'", timeout=15000)
            assert page.evaluate("document.body.dataset.replay") == "run.mcap"
            assert page.evaluate("document.getElementById('scrub').max") == str(end["seq"])
            assert "replay of run.mcap" in page.inner_text("#status")
            page.click("#live")  # "to the end"
            page.wait_for_function(
                f"document.body.dataset.shownSeq === '{end['seq']}'", timeout=15000
            )
            assert page.evaluate("Number(document.body.dataset.nodes)") == len(end["nodes"])
    finally:
        os.killpg(viewer.pid, 15)
        viewer.wait(timeout=10)


def test_a_killed_recorder_leaves_what_it_flushed(ros, tmp_path):
    from dsr_graph.protocol.replay import replay_history

    ros.procs.start_server(tmp_path / "state", world=WORLD)
    ros.procs.start(
        "recorder",
        [
            "dsr_recorder",
            "--ros-args",
            "-p",
            f"output:={tmp_path / 'cut.mcap'}",
            "-p",
            "flush_period:=0.2",
        ],
    )
    wait_for(lambda: "recording to" in ros.procs.log("recorder"), 30, "the recorder")
    for i in range(5):
        tx = {"ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": f"t{i}"}}]}
        done = ros.procs.run("dsr", "apply", "-", input=json.dumps(tx))
        assert done.returncode == 0, done.stdout + done.stderr
    time.sleep(1.0)  # several flushes
    ros.procs.kill9("recorder")
    history = replay_history(tmp_path / "cut.mcap")
    assert history.seq == 5
    assert history.graph.node("panel").attrs["text"] == "t4"
    # a recorder started again on the same name keeps the cut file and takes the next name
    ros.procs.start(
        "recorder2",
        ["dsr_recorder", "--ros-args", "-p", f"output:={tmp_path / 'cut.mcap'}"],
    )
    wait_for(lambda: "recording to" in ros.procs.log("recorder2"), 30, "the second recorder")
    assert f"recording to {tmp_path / 'cut.1.mcap'}" in ros.procs.log("recorder2")
    assert ros.procs.stop("recorder2") == 0
    assert replay_history(tmp_path / "cut.1.mcap").seq == 5
    assert replay_history(tmp_path / "cut.mcap").seq == 5


def test_dsr_writers_reads_the_run_and_the_shipped_policy_allows_what_was_written(recorded_run):
    import yaml

    from dsr_graph.model.policy import Policy

    drafted = subprocess.run(
        ["dsr", "writers", str(recorded_run / "run.mcap"), "--policy"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert drafted.returncode == 0, drafted.stderr
    draft = Policy.from_doc(yaml.safe_load(drafted.stdout))
    wrote = {rule.name for rule in draft.rules}
    assert {"/pelea", "/speech", "/panel", "/person"} <= wrote
    shipped = Policy.load(str(REPO / "src" / "clarc_bringup" / "policy" / "clarc.yaml"))
    for rule in draft.rules:  # every write of the run is one the shipped policy allows
        allowed = shipped.rule_for(rule.name)
        assert allowed is not None, rule.name
        for kind in ("nodes", "edges", "attributes"):
            for name in getattr(rule, kind):
                assert allowed.may(kind, name), (rule.name, kind, name)
