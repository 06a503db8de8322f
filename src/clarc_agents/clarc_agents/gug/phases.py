"""Timing a Get Up & Go trial from the patient's joints (pure; the gait analyser feeds it what
the DSR shows, in the chair's frame: x, y on the floor from the chair, z up, metres).

Three signals tell the whole trial: the height of the hips above the floor (up when rising,
down when sitting), their distance from the chair (out and back), and the heading of the body
from the line through the hips and the shoulders (half a turn at the far end, another one to
sit). The heading is read modulo a half turn and then made continuous, so a sensor that swaps
left and right (a Kinect when the person faces away) does not hide or invent a turn.

Robust events first place each movement: the hips' height crossing half-way between seated and
standing (with hysteresis) says when the patient was up, the distance crossing half-way to the
far point says when they were out, and the heading between those says where the turn is. Then
each movement's start and end are read from its speed in a window that holds only it and the
still spells on either side: from the moment it is half done, back and forth until it is no
longer moving (slower than a twentieth of its top speed, or than the signal's own noise); a
hesitation with a good part of the movement still to go is part of the movement. Nothing
assumes a profile of the speed: a rise, a shuffle and a steady walk are read alike. A gap of
``PAUSE`` or more between one movement's end and the next one's start is time standing still
(``still``), named apart, so a patient who stops at the far end does not lengthen the turn; a
shorter gap is split between the two.

    timed = time_trial(samples, go)
    timed.tug_seconds, timed.reaction, timed.phases["turn"], timed.still, band(tug)

The trial counts only if the patient was seated at "go", reached the line, turned round and sat
down again (``InvalidTrial`` names what failed); before the end it is ``NotATrial``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from clarc_agents.exceptions import InvalidTrial, NotATrial, TrialGap

PHASES = ("rise", "walk_out", "turn", "walk_back", "sit")
STILL = "still"  # time standing still between movements, summed
HIPS = ("pelvis", "hip_left", "hip_right")
SIDES = (("hip_left", "hip_right"), ("shoulder_left", "shoulder_right"))
MIN_MOVE = 0.2  # s: no movement of a trial is shorter
MAX_GAP = 0.5  # s without a frame that a trial may have (lost frames leave 0.1 s or so)
PAUSE = 0.5  # s between two movements that count as standing still
SETTLED = 0.5  # s seated and still before the trial is over
LINE = 3.0  # m from the chair to the line, by default
# s from "go" the whole trial may take: a patient not seated again by then cannot do the test
# this time (the trial is void; three such and the test is "unable to perform", FORMAT.md)
WITHIN = 90.0
# s from "go" a patient may take to begin to rise: one still seated then cannot get up unaided
RISE_WITHIN = 30.0
LINE_SLACK = 0.3  # m: the feet reach the line while the hips are still this far behind it
MIN_RISE = 0.15  # m the hips rise from seated to standing, at least
TURNED = 0.5 * math.pi  # rad: less than this at the far end is no turn round
SIT_TURN = 0.25 * math.pi  # rad of turning before sitting that makes it part of the sit


@dataclass(frozen=True)
class Sample:
    t: float  # seconds (of the patient's time)
    height: float  # of the hips above the floor
    distance: float  # of the hips from the chair, on the floor
    heading: float  # rad about the vertical, from the hips and shoulders (maybe half a turn off)


def sample(
    t: float, joints: dict[str, Sequence[float]], confidence: dict[str, float] | None = None
) -> Sample | None:
    """A sample from the joints of one frame (in the chair's frame); None without the hips or
    the shoulders. ``confidence``: per joint; a joint below 0.3 is not used, the others weigh
    as much as they are trusted."""
    weight = {j: 1.0 if confidence is None else confidence.get(j, 1.0) for j in joints}
    use = {j: np.asarray(p, dtype=float) for j, p in joints.items() if weight[j] >= 0.3}
    hips = [j for j in HIPS if j in use]
    if not hips:
        return None
    centre = np.average([use[j] for j in hips], axis=0, weights=[weight[j] for j in hips])
    pairs = [(a, b) for a, b in SIDES if a in use and b in use]
    if not pairs:
        return None
    left = np.average(
        [use[a] - use[b] for a, b in pairs],
        axis=0,
        weights=[weight[a] * weight[b] for a, b in pairs],
    )
    # the body faces +90 degrees from its left-to-right line, turned the other way
    heading = math.atan2(-left[0], left[1])
    return Sample(t, float(centre[2]), float(math.hypot(centre[0], centre[1])), heading)


@dataclass(frozen=True)
class TrialTimes:
    go: float
    # (start, end) of each movement in PHASES order, in the patient's time
    moves: tuple[tuple[float, float], ...]

    @property
    def tug_seconds(self) -> float:
        return self.moves[-1][1] - self.go

    @property
    def reaction(self) -> float:
        return self.moves[0][0] - self.go

    @property
    def phases(self) -> dict[str, float]:
        return {p: end - start for p, (start, end) in zip(PHASES, self.moves, strict=True)}

    @property
    def still(self) -> float:
        return sum(b[0] - a[1] for a, b in zip(self.moves, self.moves[1:], strict=False))

    @property
    def boundaries(self) -> tuple[float, ...]:
        """Every start and end, in order (a split gap gives one time twice)."""
        return tuple(t for move in self.moves for t in move)


def band(tug_seconds: float) -> str:
    """Podsiadlo & Richardson (1991)."""
    if tug_seconds < 10.0:
        return "normal"
    if tug_seconds < 20.0:
        return "mostly independent"
    if tug_seconds < 30.0:
        return "variable mobility"
    return "impaired mobility"


def fall_risk(tug_seconds: float) -> bool:
    """Shumway-Cook, Brauer & Woollacott (2000): 13.5 s or more."""
    return tug_seconds >= 13.5


def time_trial(
    samples: Sequence[Sample], go: float, holes_judged: bool = False, line: float = LINE
) -> TrialTimes:
    """The movements of the trial that began at ``go``, once the patient is seated again.
    ``holes_judged``: the caller has judged every gap between the samples as they came (the
    gait analyser), so none is checked again here. ``line``: metres from the chair the patient
    must reach."""
    samples = sorted((s for s in samples if s.t >= go), key=lambda s: s.t)
    if len(samples) < 30:
        raise NotATrial(f"{len(samples)} frames after go: too few for a trial")
    t = np.array([s.t for s in samples])
    if not holes_judged:
        check_gaps(t, go)
    height = Signal.of(np.array([s.height for s in samples]))
    distance = Signal.of(np.array([s.distance for s in samples]))
    heading = Signal.of(continuous_heading(np.array([s.heading for s in samples])))
    level_h, level_d = height.level, distance.level

    seated = float(np.median(level_h[t >= t[-1] - 0.5]))
    standing = float(np.percentile(level_h, 95))
    if standing - seated < MIN_RISE:
        raise NotATrial(f"the hips rose {standing - seated:.2f} m: the patient did not stand up")
    up = hysteresis(level_h, seated + 0.4 * (standing - seated), seated + 0.6 * (standing - seated))
    if up[-1] or not up.any():
        raise NotATrial("not seated again yet")
    at_go = float(np.median(level_h[t <= t[0] + 0.3]))
    if at_go > seated + 0.5 * (standing - seated):
        raise InvalidTrial(
            f"the patient was not seated at go (hips {at_go:.2f} m above the floor, "
            f"{seated:.2f} m when seated)"
        )
    far = float(level_d.max())
    out = np.flatnonzero(level_d > far / 2)
    t_out, t_back = t[out[0]], t[out[-1]]
    t_down = t[np.flatnonzero(up)[-1]]
    if t[-1] - t_down < 0.5 or t[-1] <= t_back or t[0] >= t_out:
        raise NotATrial("not seated again yet")
    if far < line - LINE_SLACK:
        raise InvalidTrial(
            f"the patient turned back {far:.1f} m from the chair: the line is at {line:g} m"
        )
    back, out_heading = heading.raw[(t > t_back) & (t <= t_down)], heading.raw[t < t_out]
    turned = abs(np.median(back) - np.median(out_heading))
    if turned < TURNED:
        raise InvalidTrial(
            f"the patient did not turn round at the far end ({math.degrees(turned):.0f} degrees)"
        )

    rise = transition(t, height, go, t_out)
    drop = transition(t, height, t_back, t[-1])
    if drop.end > t[-1] - SETTLED:
        raise NotATrial("still sitting down")
    turn = transition(t, heading, t_out, t_back)
    walk_out = transition(t, distance, rise.end, turn.start)
    walk_back = transition(t, distance, turn.end, drop.start)
    # turning round to the chair before sitting is part of the sit (turn-to-sit)
    sit_start = drop.start
    if drop.start - walk_back.end > MIN_MOVE:
        last_turn = transition(t, heading, walk_back.end, t[-1])
        if abs(last_turn.step) >= SIT_TURN:
            sit_start = min(sit_start, last_turn.start)
    moves = [
        (max(rise.start, go), rise.end),
        (walk_out.start, walk_out.end),
        (turn.start, turn.end),
        (walk_back.start, walk_back.end),
        (sit_start, drop.end),
    ]
    return TrialTimes(go, tuple(in_order(moves)))


def in_order(moves: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The movements with their meetings settled: where one ends less than ``PAUSE`` before
    the next starts (or after it), both meet half-way; a longer gap stays (standing still)."""
    moves = [list(m) for m in moves]
    for a, b in zip(moves, moves[1:], strict=False):
        if b[0] - a[1] < PAUSE:
            a[1] = b[0] = (a[1] + b[0]) / 2
    for m in moves:  # a movement squeezed by both neighbours still lasts no less than nothing
        m[1] = max(m[1], m[0])
    return [(a, b) for a, b in moves]


def check_gaps(t: np.ndarray, go: float) -> None:
    """``TrialGap`` if the frames from ``go`` on leave a hole longer than ``MAX_GAP``."""
    steps = np.diff(np.concatenate(([go], t)))
    worst = int(np.argmax(steps))
    if steps[worst] > MAX_GAP:
        at = go if worst == 0 else t[worst - 1]
        raise TrialGap(
            f"no frames for {steps[worst]:.1f} s from {at - go:.1f} s after go: "
            "the trial cannot be timed"
        )


# ------------------------------------------------------------------ signals
def half_turn_step(before: float, after: float) -> float:
    """The turn from heading ``before`` to ``after`` (rad), read modulo half a turn: the
    smallest, so a left/right swap (half a turn in one frame) adds nothing."""
    step = 2.0 * (after - before)
    return ((step + math.pi) % (2.0 * math.pi) - math.pi) / 2.0


def continuous_heading(heading: np.ndarray) -> np.ndarray:
    """The heading made continuous, read modulo half a turn (a left/right swap is half a turn
    in one frame: no body turns that fast, so it is taken out), from 0 at the first frame."""
    doubled = np.unwrap(2.0 * np.asarray(heading, dtype=float))
    return (doubled - doubled[0]) / 2.0


@dataclass(frozen=True)
class Signal:
    """One of a trial's signals, its running median (``level``) and the noise left in that."""

    raw: np.ndarray
    level: np.ndarray
    noise: float

    @classmethod
    def of(cls, raw: np.ndarray) -> Signal:
        level = running_median(raw)
        return cls(raw, level, level_noise(raw, level))


def running_median(y: np.ndarray, width: int = 0) -> np.ndarray:
    """Each value replaced by the median of ``width`` around it (an outlier frame, a joint
    jumping, does not move a level or a crossing)."""
    width = width or MEDIAN
    if len(y) < width:
        return y.copy()
    half = width // 2
    padded = np.concatenate((np.full(half, y[0]), y, np.full(half, y[-1])))
    windows = np.lib.stride_tricks.sliding_window_view(padded, width)
    return np.median(windows, axis=1)


def hysteresis(y: np.ndarray, low: float, high: float) -> np.ndarray:
    """True from where ``y`` rises above ``high`` until it falls below ``low`` (noise between
    the two does not flicker it)."""
    out = np.zeros(len(y), dtype=bool)
    state = False
    for i, v in enumerate(y):
        state = v > low if state else v > high
        out[i] = state
    return out


# ------------------------------------------------------------------ one movement
GRID = 1.0 / 30.0  # s: signals are read on an even grid (frames come unevenly)
# s either side: a speed is the change over this much time before and after; the shortest whose
# noise stays under QUIET of the movement's top speed (noisy frames need a longer look)
SPEED_OVER = (0.2, 0.3, 0.45)
QUIET = 0.1
SLOWEST = 0.06  # of the movement's top speed: slower than this is not moving
NOISE = 3.0  # standard deviations of the speed noise alone gives: slower is noise
MEDIAN = 7  # frames a level is the median of
ARRIVED = 0.1  # of a movement's whole change still to go: a stop before it is a hesitation


@dataclass(frozen=True)
class Transition:
    start: float
    end: float
    step: float  # the level after minus the level before


def level_noise(y: np.ndarray, level: np.ndarray) -> float:
    """The noise left in ``level``, ``y``'s running median (its standard deviation): the
    frame-to-frame noise read off what the running median removes, which a movement hardly
    changes, and a median of ``MEDIAN`` keeps about 1.25 / sqrt(``MEDIAN``) of it."""
    if len(y) < 2 * MEDIAN:
        return 0.0
    sigma = 1.4826 * float(np.median(np.abs(y - level)))
    return 1.25 * sigma / math.sqrt(MEDIAN)


def transition(t: np.ndarray, signal: Signal, lo: float, hi: float) -> Transition:
    """The movement ``signal`` makes between its level at ``lo`` and its level at ``hi``: from
    where its speed, going back from the moment it is half-way, falls to ``SLOWEST`` of its top
    speed (or to what ``NOISE`` times its noise gives), to where it falls so going forward; a
    stop with more than ``ARRIVED`` of the change still to go is a hesitation inside the
    movement, not its end."""
    if hi - lo < MIN_MOVE or np.count_nonzero((t >= lo) & (t <= hi)) < 10:
        raise NotATrial(f"too little of the trial between {lo:.1f} s and {hi:.1f} s")
    grid = np.arange(lo, hi + GRID / 2, GRID)
    level = np.interp(grid, t, signal.level)
    # the levels either side: the 0.3 s just outside the window where the trial has them (the
    # movement before this one has ended there), else the window's own first and last 0.3 s
    before = _level_near(t, signal.level, lo - 0.3, lo, level[grid <= lo + 0.3])
    after = _level_near(t, signal.level, hi, hi + 0.3, level[grid >= hi - 0.3])
    step = after - before
    if step == 0.0:
        raise NotATrial(f"no movement between {lo:.1f} s and {hi:.1f} s")
    for over in SPEED_OVER:
        v = _speed(t, signal.level, grid, over) * math.copysign(1.0, step)
        floor = NOISE * signal.noise * math.sqrt(2.0) / (2.0 * over)
        if floor <= QUIET * float(v.max()):
            break
    done = (level - before) / step  # 0 before the movement, 1 after it
    half = int(np.argmax(done >= 0.5))
    moving = v > max(floor, SLOWEST * float(v.max()))
    first = last = half
    while True:
        while first > 0 and moving[first - 1]:
            first -= 1
        earlier = np.flatnonzero(moving[:first])
        if first == 0 or done[first] < ARRIVED or not len(earlier):
            break
        first = int(earlier[-1])
    while True:
        while last < len(grid) - 1 and moving[last + 1]:
            last += 1
        later = np.flatnonzero(moving[last + 1 :])
        if last == len(grid) - 1 or done[last] > 1.0 - ARRIVED or not len(later):
            break
        last = last + 1 + int(later[0])
    return Transition(float(grid[first]), float(grid[last]), step)


def _level_near(t, level, lo: float, hi: float, otherwise: np.ndarray) -> float:
    near = level[(t >= lo) & (t <= hi)]
    return float(np.median(near if len(near) >= 3 else otherwise))


def _speed(t: np.ndarray, level: np.ndarray, grid: np.ndarray, over: float) -> np.ndarray:
    """The speed of ``level`` at each time of ``grid``: the change from ``over`` s before to
    ``over`` s after."""
    ahead = np.interp(grid + over, t, level)
    behind = np.interp(grid - over, t, level)
    return (ahead - behind) / (2 * over)
