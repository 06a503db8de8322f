"""Scenario files for the simulated patient (YAML), checked strictly: a mistake is a load error
that names the line (pure; no ROS).

    patient: Carlos
    items:        # an item not listed is answered by voice with its highest option
      feeding:  {answer: 10, via: voice}
      bathing:  {answer: 0, via: touch}
      grooming: {via: silence}                           # silent on both tries -> unanswered
      dressing: {answer: 5, via: voice, first: garbled}  # first try not understood
      bowels:   {answer: 10, via: voice, first: silence} # silent once, answers on the second try
      stairs:   {answer: 5, via: touch, leave: 2.0}      # walks away while asked, back after 2.0 s

``answer`` is the points of the chosen option; ``via`` is voice, touch or silence; ``first`` (what
happens on the first try) is garbled or silence; ``leave`` is how many seconds (scaled with every
other time) the patient is away after walking off when the item is introduced.

Any questionnaire test (a file in clarc_agents/definitions) is played the same way, saying which
(``test: barthel`` may be left out): ``test: lawton``, or ``test: mmse``, whose items are scored,
not chosen, so each says the ``points`` the patient earns (``answer`` and ``points`` are one key
by two names) and how (an item not listed earns its maximum, the way its kind is answered):

    test: mmse
    patient: Carlos
    items:
      recall:   {points: 2, via: voice}      # two of the three words right
      command:  {points: 1, via: touch}      # the first shape right, two wrong
      reading:  {points: 0}                  # does not close the eyes
      writing:  {via: silence}               # writes nothing, twice -> unanswered

``via`` must be a way the item is answered (voice for said items, touch for the command, the
writing and the copying); "close your eyes" is seen by the camera, whatever ``via`` says (a
patient who does not close them, silent or not, is asked twice and scores 0). The
points of a writing or a copying are what the clinician would give the drawing (a line of
handwriting or the pentagons for 1, a scribble for 0): they are scored in the dashboard.

A questionnaire is asked and answered in English unless the scenario says another language its
test is shipped in (``language: es``: the Barthel, the Lawton and the Mini-Mental,
clarc_agents/definitions/es/); the patient then says its answers in that language.

With ``--audio`` the patient speaks with its own voice in a noisy room (optional, these defaults;
the voice is the scenario's language's own, ``es`` for Spanish):

    voice: {name: en-us, rate: 150, pitch: 50}   # an espeak-ng voice, words a minute, 0-99
    room: {noise: white, snr_db: 30}             # white, babble or television; dB over the noise

A Get Up & Go scenario says ``test: get_up_and_go``:

    test: get_up_and_go
    patient: Carlos
    motion: {reaction: 1.0, rise: 2.0, walk_out: 4.0, turn: 2.0, walk_back: 4.0, sit: 3.0}
    noise_mm: 10      # optional: joint noise (standard deviation, mm; slow, as a Kinect's is)
    drop_rate: 0.1    # optional: share of Kinect frames lost
    tracking_losses: 2  # optional: brief spells (0.1-0.35 s) the Kinect sees no body
    leave: 6.0        # optional: walks out of view this long after "go", once
    rises: false      # optional: cannot get up (each trial void: "unable to perform")

``motion`` gives the seconds of each part of the trial in the patient's time (all six, each
positive but ``reaction``, which may be 0); their sum is the truth a measured ``tug_seconds`` is
checked against. Instead of ``motion``, a scenario may play recorded movement:

    recording: recordings/tug_f77.csv   # a skeleton recording (clarc skeleton import)
    offset: 0.0       # optional: seconds into the recording at "go"

the path relative to the scenario's file. The recording is read and placed in the trial when the
scenario is loaded (a file that cannot be is a scenario error naming the line).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from clarc_agents import definitions
from clarc_agents.definitions import Definition
from clarc_agents.exceptions import ScenarioError
from clarc_agents.yaml_lines import compose, fields
from clarc_agents.yaml_lines import err as _err
from clarc_agents.yaml_lines import scalar as _scalar
from clarc_sim.patient.gait_motion import Motion

# the room's noises a scenario may name (devices/sound.py makes each)
NOISES = ("white", "babble", "television")

TIMED = "get_up_and_go"


def voice_for(language: str) -> str:
    """espeak-ng's voice for a language a test is asked in: American English for English (the
    suite's voice), else the language's own (``es``: Castilian Spanish); the robot's and, unless
    a scenario names one, the patient's."""
    return "en-us" if language == "en" else language


MOTION_KEYS = ("reaction", "rise", "walk_out", "turn", "walk_back", "sit")
GUG_KEYS = (
    "test",
    "patient",
    "motion",
    "recording",
    "offset",
    "noise_mm",
    "drop_rate",
    "tracking_losses",
    "leave",
    "rises",
)

VIAS = ("voice", "touch", "camera", "silence")
FIRSTS = ("garbled", "silence")
ITEM_KEYS = ("answer", "points", "via", "first", "leave")


@dataclass(frozen=True)
class ItemPlan:
    item: str
    answer: int | None  # the points earned; None with via: silence
    via: str
    first: str | None = None
    leave: float | None = None


@dataclass
class Scenario:
    patient: str
    items: dict[str, ItemPlan] = field(default_factory=dict)
    source: str = ""
    test: str = "barthel"
    motion: Motion | None = None  # get_up_and_go, scripted
    recording: str | None = None  # get_up_and_go, played: the skeleton recording's path
    offset: float = 0.0  # seconds into the recording at "go"
    noise_mm: float = 0.0
    drop_rate: float = 0.0
    tracking_losses: int = 0
    leave: float | None = None  # seconds after "go" the patient walks out of view
    rises: bool = True  # False: stays seated whatever is said (cannot do the test)
    voice: tuple[str, int, int] = ("en-us", 150, 50)  # --audio: espeak-ng voice, wpm, pitch
    noise: str = "white"  # --audio: the room's noise
    snr_db: float = 30.0  # --audio: the patient's voice over the room's noise
    language: str = "en"  # what the test is asked and answered in

    def plan(self, item: str) -> ItemPlan:
        return self.items[item]


def parse(text: str, source: str = "scenario") -> Scenario:
    root = compose(text, source)
    if not isinstance(root, yaml.MappingNode):
        raise _err(source, root, 'a scenario is a mapping with "patient" and "items"')
    patient, items_node = None, None
    test = next((_scalar(v) for k, v in root.value if _scalar(k) == "test"), "barthel")
    tests = definitions.tests() + (TIMED,)
    if test not in tests:
        node = next(v for k, v in root.value if _scalar(k) == "test")
        raise _err(source, node, f"test must be one of {', '.join(tests)}, got {test!r}")
    if test == TIMED:
        return _get_up_and_go(source, root)
    language = "en"
    sound: dict[str, Any] = {}
    for key_node, value_node in root.value:
        key = _scalar(key_node)
        if key == "test":
            continue
        if key == "language":
            language = _scalar(value_node)
            shipped = definitions.languages(test)
            if language not in shipped:
                raise _err(
                    source,
                    value_node,
                    f"{test} is shipped in {', '.join(shipped)}, not in {language!r}",
                )
            continue
        if key == "patient":
            patient = _scalar(value_node)
            if not isinstance(patient, str) or not patient.strip():
                raise _err(source, value_node, '"patient" must be a name')
        elif key == "items":
            items_node = value_node
        elif key in ("voice", "room"):
            sound[key] = value_node
        else:
            raise _err(
                source,
                key_node,
                f"unknown key {key!r} (a scenario has patient and items, and language, voice "
                "and room)",
            )
    if patient is None:
        raise _err(source, root, 'missing "patient"')
    definition = definitions.load(test, language)
    scenario = Scenario(
        patient.strip(),
        source=source,
        test=test,
        language=language,
        **_sound(source, sound, language),
    )
    listed: dict[str, ItemPlan] = {}
    if items_node is not None and not (
        isinstance(items_node, yaml.ScalarNode) and _scalar(items_node) is None
    ):
        if not isinstance(items_node, yaml.MappingNode):
            raise _err(source, items_node, '"items" maps item names to what the patient does')
        for key_node, value_node in items_node.value:
            item = _scalar(key_node)
            if item not in definition.order:
                raise _err(
                    source,
                    key_node,
                    f"unknown item {item!r}; the items are {', '.join(definition.order)}",
                )
            if item in listed:
                raise _err(source, key_node, f"item {item!r} is listed twice")
            listed[item] = _item(source, definition, item, value_node)
    for spec in definition.items:
        plan = ItemPlan(spec.key, spec.max, spec.via[0])
        scenario.items[spec.key] = listed.get(spec.key, plan)
    return scenario


def _sound(source: str, nodes: dict[str, Any], language: str) -> dict[str, Any]:
    """``voice: {name, rate, pitch}`` and ``room: {noise, snr_db}`` (--audio), checked; the
    voice is the language's own unless named."""
    out: dict[str, Any] = {"voice": (voice_for(language), 150, 50)}
    if "voice" in nodes:
        keys = ("name", "rate", "pitch")
        got = fields(source, nodes["voice"], (), "voice: ", keys)
        name, rate, pitch = out["voice"]
        for key, (_, node) in got.items():
            value = _scalar(node)
            if key == "name" and not (isinstance(value, str) and value.strip()):
                raise _err(source, node, "voice: name is an espeak-ng voice (en-us, en-gb, ...)")
            limits = {"rate": (80, 450), "pitch": (0, 99)}.get(key)
            if limits and (
                isinstance(value, bool)
                or not isinstance(value, int)
                or not limits[0] <= value <= limits[1]
            ):
                raise _err(
                    source,
                    node,
                    f"voice: {key} is a whole number from {limits[0]} to "
                    f"{limits[1]}, got {value!r}",
                )
            name, rate, pitch = (
                value if key == "name" else name,
                value if key == "rate" else rate,
                value if key == "pitch" else pitch,
            )
        out["voice"] = (name.strip(), rate, pitch)
    if "room" in nodes:
        got = fields(source, nodes["room"], (), "room: ", ("noise", "snr_db"))
        for key, (_, node) in got.items():
            value = _scalar(node)
            if key == "noise" and value not in NOISES:
                raise _err(
                    source, node, f"room: noise is one of {', '.join(NOISES)}, got {value!r}"
                )
            if key == "snr_db" and (
                isinstance(value, bool)
                or not isinstance(value, (int, float))
                or not -5 <= value <= 60
            ):
                raise _err(
                    source, node, f"room: snr_db is a number of dB from -5 to 60, got {value!r}"
                )
            out[key] = float(value) if key == "snr_db" else value
    return out


def _item(source: str, definition: Definition, item: str, node: Any) -> ItemPlan:
    spec = definition.item(item)
    if not isinstance(node, yaml.MappingNode):
        raise _err(source, node, f"{item}: expected a mapping like {{answer: 10, via: voice}}")
    values = {
        key: (_scalar(value_node), value_node)
        for key, (_, value_node) in fields(source, node, (), f"{item}: ", ITEM_KEYS).items()
    }
    if "answer" in values and "points" in values:
        raise _err(source, node, f"{item}: answer and points are the same key; give one")
    via, via_node = values.get("via", (spec.via[0], node))
    if via not in VIAS:
        raise _err(source, via_node, f"{item}: via must be one of {', '.join(VIAS)}, got {via!r}")
    if spec.kind == "eyes" and via != "silence":
        via = "camera"  # whatever the scenario says, the camera sees the eyes close
    if via not in spec.via + ("silence",):
        raise _err(
            source,
            via_node,
            f"{item}: via must be {' or '.join(spec.via + ('silence',))} for this item, "
            f"got {via!r}",
        )
    answer, answer_node = values.get("answer", values.get("points", (None, node)))
    if via == "silence":
        if "answer" in values:
            raise _err(
                source, answer_node, f'{item}: a silent patient gives no answer; drop "answer"'
            )
    else:
        if answer is None:
            answer = spec.max
        if isinstance(answer, bool) or not isinstance(answer, int) or answer not in spec.points:
            what = "an option; the options are" if spec.kind == "choose" else "a score; it is"
            raise _err(
                source,
                answer_node,
                f"{item}: {'points' if 'points' in values else 'answer'} {answer!r} is not "
                f"{what} {', '.join(str(p) for p in spec.points)} points",
            )
    first, first_node = values.get("first", (None, node))
    if first is not None and first not in FIRSTS:
        raise _err(
            source, first_node, f"{item}: first must be one of {', '.join(FIRSTS)}, got {first!r}"
        )
    leave, leave_node = values.get("leave", (None, node))
    if leave is not None and (
        isinstance(leave, bool) or not isinstance(leave, (int, float)) or leave < 0
    ):
        raise _err(source, leave_node, f"{item}: leave is a number of seconds, got {leave!r}")
    return ItemPlan(item, answer, via, first, None if leave is None else float(leave))


def _get_up_and_go(source: str, root: Any) -> Scenario:
    values = {}
    for key_node, value_node in root.value:
        key = _scalar(key_node)
        if key not in GUG_KEYS:
            raise _err(
                source,
                key_node,
                f"unknown key {key!r} (a get_up_and_go scenario has {', '.join(GUG_KEYS)})",
            )
        values[key] = value_node
    patient = _scalar(values.get("patient"))
    if not isinstance(patient, str) or not patient.strip():
        raise _err(source, values.get("patient", root), '"patient" must be a name')
    scenario = Scenario(patient.strip(), source=source, test="get_up_and_go")
    if "recording" in values:
        _recording(source, values, scenario)
    else:
        scenario.motion = _motion(source, values.get("motion"), root)
        if "offset" in values:
            raise _err(source, values["offset"], '"offset" goes with a "recording"')
    if "noise_mm" in values:
        scenario.noise_mm = _number(source, values["noise_mm"], "noise_mm")
    if "drop_rate" in values:
        scenario.drop_rate = _number(source, values["drop_rate"], "drop_rate")
        if scenario.drop_rate >= 1.0:
            raise _err(source, values["drop_rate"], "drop_rate is a share of frames below 1")
    if "tracking_losses" in values:
        losses = _scalar(values["tracking_losses"])
        if isinstance(losses, bool) or not isinstance(losses, int) or not 0 <= losses <= 20:
            raise _err(source, values["tracking_losses"], "tracking_losses is a count, 0 to 20")
        scenario.tracking_losses = losses
    if "leave" in values:
        scenario.leave = _number(source, values["leave"], "leave")
    if "rises" in values:
        rises = _scalar(values["rises"])
        if not isinstance(rises, bool):
            raise _err(source, values["rises"], f"rises is true or false, got {rises!r}")
        scenario.rises = rises
    return scenario


def _motion(source: str, node: Any, root: Any) -> Motion:
    if not isinstance(node, yaml.MappingNode):
        raise _err(
            source,
            node or root,
            f'"motion" maps {", ".join(MOTION_KEYS)} to seconds of the patient\'s time '
            '(or "recording" names a skeleton recording)',
        )
    # a patient may start to rise as "go" ends; every movement takes some time
    seconds = {
        key: _number(source, value_node, f"motion: {key}", positive=key != "reaction")
        for key, (_, value_node) in fields(source, node, MOTION_KEYS, "motion: ").items()
    }
    return Motion(**seconds)


def _recording(source: str, values: dict[str, Any], scenario: Scenario) -> None:
    """``recording:`` (and ``offset:``): the file is read and placed now, so a bad one is the
    scenario's error, on its line."""
    from clarc_sim.patient import skeleton_recording

    node = values["recording"]
    if "motion" in values:
        raise _err(source, values["motion"], 'a scenario has "motion" or "recording", not both')
    name = _scalar(node)
    if not isinstance(name, str) or not name.strip():
        raise _err(source, node, '"recording" must name a skeleton recording file')
    path = Path(name)
    if not path.is_absolute() and source not in ("", "scenario"):
        path = Path(source).resolve().parent / path
    try:
        recording = skeleton_recording.placed(skeleton_recording.read(path))
    except ScenarioError as e:
        raise _err(source, node, f"recording: {e}") from None
    scenario.recording = str(path)
    if "offset" in values:
        scenario.offset = _number(source, values["offset"], "offset")
        if scenario.offset >= recording.duration:
            raise _err(
                source,
                values["offset"],
                f"offset {scenario.offset:g} s is past the recording's end "
                f"({recording.duration:.1f} s)",
            )


def _number(source: str, node: Any, what: str, positive: bool = False) -> float:
    value = _scalar(node)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != value:
        raise _err(source, node, f"{what} must be a number, got {value!r}")
    if value < 0 or (positive and value == 0):
        raise _err(source, node, f"{what} must be {'above' if positive else 'at least'} 0")
    return float(value)


def load(path: str) -> Scenario:
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise ScenarioError(f"{path}: cannot read: {e.strerror}") from None
    return parse(text, source=str(path))
