"""``workcell train``: train a LeRobot policy on a Workcell export (the learn extra)."""

from __future__ import annotations

import argparse
import contextlib
import json
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from workcell.errors import ConfigError
from workcell.learn.train_options import DEFAULT_THREADS

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.learn.train import TrainProgress

MAX_EPISODE = 10_000_000
MAX_OWN_WORLD_SESSIONS = 3
"""Up to this many demonstration sessions, the closing hint also replays their very worlds
(one command each)."""


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "train",
        help="train a LeRobot policy (ACT, diffusion) on a LeRobot export",
        description=(
            "Run LeRobot's own training (lerobot-train) on a dataset written by 'workcell "
            "export --format lerobot', offline, with defaults that train a state-only policy "
            "on a CPU in well under an hour. Writes LeRobot's log to OUT/train.log from the "
            "start and LeRobot's standard checkpoint under "
            "OUT/checkpoints/last/pretrained_model, every tenth of the steps (so a run cut "
            "short leaves one); drive with it by 'workcell collect --operator policy:OUT'. "
            "Needs the learn extra (pip install 'workcell[learn]')."
        ),
    )
    parser.add_argument(
        "--dataset", required=True, type=Path, metavar="DIR", help="a LeRobot export"
    )
    parser.add_argument(
        "--policy", default="act", metavar="{act,diffusion}", help="policy type (default: act)"
    )
    parser.add_argument(
        "--out", required=True, type=Path, metavar="DIR", help="new or empty directory"
    )
    parser.add_argument("--steps", type=int, default=10_000, help="training steps (default: 10000)")
    parser.add_argument("--batch-size", type=int, default=32, help="batch size (default: 32)")
    parser.add_argument(
        "--episodes",
        metavar="LIST",
        help="train on these episodes only, e.g. 0-24 or 0,3,5-9 (default: all)",
    )
    parser.add_argument(
        "--device", default="auto", metavar="{auto,cpu,cuda}", help="auto: cuda when available"
    )
    parser.add_argument("--seed", type=int, default=1000, help="training seed (default: 1000)")
    parser.add_argument(
        "--threads",
        type=int,
        default=DEFAULT_THREADS,
        help=f"torch threads (default: {DEFAULT_THREADS}, beside one data-loading worker, as "
        "the published timings ran; a thread per core crawls on a machine busy with other "
        "work: on a shared 2-core machine 2.9-13 s a step against 0.3-2.3 s with one, and "
        "5 times the CPU time; more pay only on idle cores; 0: torch's own default, a "
        "thread per core)",
    )
    parser.add_argument(
        "--save-every",
        type=int,
        metavar="N",
        help="keep a checkpoint every N steps (default: one every tenth of the steps, only "
        "the newest kept)",
    )
    parser.add_argument(
        "--correction-weight",
        type=int,
        metavar="K",
        help="train on demonstrations plus corrections, as HG-DAgger aggregates them: an "
        "episode with corrected frames (intervention = true) contributes only its corrected "
        "stretches, each repeated K times (LeRobot has no per-sample weights, so repetition "
        "is the weight; 1: counted once), every other episode is kept whole; the dataset "
        "trained on is written to OUT-dataset, beside OUT (state-only exports; default: "
        "every frame of every episode, as exported)",
    )
    parser.add_argument(
        "--lerobot",
        action="append",
        default=[],
        metavar="--KEY=VALUE",
        help="pass an option to lerobot-train after the defaults, e.g. "
        "--lerobot=--policy.dim_model=512 (repeatable)",
    )
    parser.set_defaults(func=run)


def parse_episodes(text: str) -> tuple[int, ...]:
    """``"0-2,5"`` → (0, 1, 2, 5)."""
    episodes: list[int] = []
    for part in text.split(","):
        first, _, last = part.strip().partition("-")
        try:
            low = int(first)
            high = int(last) if last else low
        except ValueError:
            raise ConfigError(
                [f"--episodes {text!r}: must be indices and ranges, e.g. 0-24 or 0,3,5-9"]
            ) from None
        if not 0 <= low <= high <= MAX_EPISODE:
            raise ConfigError([f"--episodes {text!r}: {part.strip()!r} is not a range a-b, a <= b"])
        episodes.extend(range(low, high + 1))
    return tuple(sorted(set(episodes)))


def run(args: argparse.Namespace) -> int:
    from workcell.learn.train import (  # noqa: PLC0415
        run_training,
        thread_environment,
        train_command,
    )
    from workcell.learn.train_options import TrainOptions  # noqa: PLC0415

    dataset = args.dataset
    if args.correction_weight is not None:
        dataset = _with_corrections(args.dataset, args.out, args.correction_weight)
    options = TrainOptions(
        dataset=dataset,
        out=args.out,
        policy=args.policy,
        steps=args.steps,
        batch_size=args.batch_size,
        episodes=None if args.episodes is None else parse_episodes(args.episodes),
        device=args.device,
        seed=args.seed,
        threads=args.threads,
        save_every=args.save_every,
        extra=tuple(args.lerobot),
    )
    command, device = train_command(options)
    variables = [f"{key}={value}" for key, value in thread_environment(options).items()]
    print(f"training {options.policy} on {device} for {options.steps} steps; LeRobot's command:")
    print("  " + shlex.join([*variables, "lerobot-train", *command[3:]]), flush=True)
    print(f"LeRobot's log: {options.out / 'train.log'}", flush=True)
    bar = _ProgressBar()
    result = run_training(options, bar.show)
    bar.finish()
    loss = f", final loss {result.last.loss:.4g}" if result.last is not None else ""
    print(
        f"trained in {result.seconds / 60:.1f} min{loss}\n"
        f"checkpoint: {result.checkpoint.path}\n"
        f"operator id: {result.checkpoint.operator_id}"
    )
    for line in evaluation_hint(args.dataset, options.out):
        print(line)
    return 0


def _with_corrections(dataset: Path, out: Path, weight: int) -> Path:
    from workcell.learn.corrections import aggregate, aggregated_path, check_weight  # noqa: PLC0415
    from workcell.learn.train import check_dataset  # noqa: PLC0415

    check_weight(weight)
    check_dataset(dataset)
    built = aggregated_path(out)
    plan = aggregate(dataset, built, weight)
    stretches = sum(1 for s in plan.stretches if s.corrected) // weight
    print(
        f"demonstrations plus corrections: {plan.demonstration_frames} demonstration frames, "
        f"{stretches} corrected stretch(es) x {weight} = {plan.corrected_frames} frames; "
        f"written to {built}",
        flush=True,
    )
    if plan.left_out:
        print(
            f"left out {len(plan.left_out)} episode(s) a policy drove that nobody corrected "
            f"(episode index {', '.join(map(str, plan.left_out))}): not demonstrations",
            flush=True,
        )
    return built


def evaluation_seed(dataset: Path) -> int:
    """The first seed from 1000 on that none of the dataset's sessions used (the export's
    provenance names them), so that an evaluation meets new worlds."""
    used = set()
    for session in _sessions(dataset):
        with contextlib.suppress(KeyError, TypeError, ValueError):
            used.add(int(session["seed"]))
    seed = 1000
    while seed in used:
        seed += 1
    return seed


def world_flags(dataset: Path) -> list[list[str]]:
    """The flags of ``collect`` that put a session in the world each of the dataset's
    sessions ran in (``--world D1``, or ``--set world.randomization.KEY=VALUE`` for ranges
    of no named world; ``--task`` for a task other than the default), one list per
    distinct world in order of first appearance; none when the provenance says nothing."""
    found: dict[tuple[str, ...], None] = {}
    for session in _sessions(dataset):
        try:
            found[tuple(_world_flags_of(session["parameters"]))] = None
        except (KeyError, TypeError, AttributeError, ValueError, ConfigError):
            continue
    return [list(flags) for flags in found]


def own_worlds(dataset: Path) -> list[tuple[list[str], int, int]]:
    """For each session the dataset's episodes came from, in order of first appearance: the
    flags of its world, its seed, and how many trials reach its last exported trial. A
    ``collect`` with them meets the very worlds of those demonstrations: a trial's world is
    fixed by its session's seed and its index (``trial_seed`` in task/runner.py). None for
    a session the provenance does not describe."""
    provenance = _provenance(dataset)
    last: dict[str, int] = {}
    for episode in provenance.get("episodes", []):
        with contextlib.suppress(KeyError, TypeError, ValueError):
            session, index = str(episode["session_id"]), int(episode["trial_index"])
            last[session] = max(last.get(session, 0), index + 1)
    sessions = provenance.get("sessions", {})
    found = []
    for session_id, trials in last.items():
        try:
            session = sessions[session_id]
            found.append((_world_flags_of(session["parameters"]), int(session["seed"]), trials))
        except (KeyError, TypeError, AttributeError, ValueError, ConfigError):
            continue
    return found


def evaluation_hint(dataset: Path, out: Path) -> list[str]:
    """How to evaluate the trained policy: in the very worlds of its demonstrations (for a
    dataset of up to :data:`MAX_OWN_WORLD_SESSIONS` sessions), then in new worlds drawn as
    theirs were, as two conditions of one store that the audit compares."""
    seed = evaluation_seed(dataset)
    worlds = world_flags(dataset) or [[]]
    own = own_worlds(dataset)
    named = "; ".join(" ".join(flags) or "the default world" for flags in worlds)
    policy = ["workcell", "collect", "--operator", f"policy:{out}"]
    store = ["--store", "eval.sqlite"]
    new_worlds = [
        [*policy, *flags, "--mode", "collection", "--trials", "200", "--seed", str(seed)]
        for flags in worlds
    ]
    if not own or len(own) > MAX_OWN_WORLD_SESSIONS:
        return [
            f"evaluate it in new worlds of its demonstrations' kind ({named}; seeds none of "
            "them used):",
            *("  " + shlex.join([*command, *store]) for command in new_worlds),
            "  workcell audit --store eval.sqlite --out report",
        ]
    own_commands = [
        [*policy, *flags, "--mode", "collection", "--trials", str(trials), "--seed", str(first)]
        for flags, first, trials in own
    ]
    return [
        "evaluate it in the very worlds of its demonstrations (their sessions' seeds), then "
        f"in new worlds of their kind ({named}; seeds none of them used), and compare:",
        *("  " + shlex.join([*c, "--condition", "own-worlds", *store]) for c in own_commands),
        *("  " + shlex.join([*c, "--condition", "new-worlds", *store]) for c in new_worlds),
        "  workcell audit --store eval.sqlite --out report --by condition",
    ]


def _sessions(dataset: Path) -> list[dict[str, Any]]:
    """The sessions the export's provenance lists (none when it cannot be read)."""
    sessions = _provenance(dataset).get("sessions", {})
    try:
        return [s for s in sessions.values() if isinstance(s, dict)]
    except AttributeError:
        return []


def _provenance(dataset: Path) -> dict[str, Any]:
    """The export's provenance (empty when it cannot be read)."""
    from workcell.export.lerobot_layout import PROVENANCE_JSON_PATH  # noqa: PLC0415

    try:
        provenance = json.loads((dataset / PROVENANCE_JSON_PATH).read_text())
    except (OSError, ValueError):
        return {}
    return provenance if isinstance(provenance, dict) else {}


def _world_flags_of(parameters: dict[str, Any]) -> list[str]:
    from workcell.sim.randomization import RandomizationConfig  # noqa: PLC0415
    from workcell.tasks import WORLDS, world_of  # noqa: PLC0415
    from workcell.tasks.registry import DEFAULT_TASK, task_class  # noqa: PLC0415

    kind = str(parameters.get("task", {}).get("kind", DEFAULT_TASK))
    ranges = {k: float(v) for k, v in parameters["world"]["randomization"].items()}
    flags = [] if kind == DEFAULT_TASK else ["--task", kind]
    name = world_of(task_class(kind).worlds, RandomizationConfig(**ranges))
    if name in WORLDS:
        return [*flags, "--world", name]
    for key, value in ranges.items():
        if value:
            flags += ["--set", f"world.randomization.{key}={value:g}"]
    return flags


class _ProgressBar:
    """One line, rewritten in place on a terminal. Otherwise a line for the first report,
    then at each tenth of the run and whenever a minute has passed since the last line."""

    WIDTH = 30
    EVERY_S = 60.0

    def __init__(self) -> None:
        self.live = sys.stderr.isatty()
        self._shown_tenth = -1
        self._shown_s: float | None = None

    def show(self, progress: TrainProgress) -> None:
        share = min(1.0, progress.step / max(1, progress.steps))
        filled = round(share * self.WIDTH)
        left = progress.remaining_s
        eta = "" if left is None else f", {left / 60:.1f} min left"
        text = (
            f"[{'#' * filled}{'.' * (self.WIDTH - filled)}] step {progress.step}/"
            f"{progress.steps}  loss {progress.loss:.4g}  {progress.steps_per_s:.2f} steps/s{eta}"
        )
        if self.live:
            print(f"\r{text}  ", end="", file=sys.stderr, flush=True)
            return
        tenth = int(share * 10)
        due = self._shown_s is None or progress.elapsed_s - self._shown_s >= self.EVERY_S
        if tenth > self._shown_tenth or due:
            self._shown_tenth = tenth
            self._shown_s = progress.elapsed_s
            print(text, file=sys.stderr, flush=True)

    def finish(self) -> None:
        if self.live:
            print(file=sys.stderr)
