"""``workcell train``: train a LeRobot policy on a Workcell export (the learn extra)."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from workcell.errors import ConfigError

if TYPE_CHECKING:
    from workcell.cli.command import Subparsers
    from workcell.learn.train import TrainProgress

MAX_EPISODE = 10_000_000


def register(subparsers: Subparsers) -> None:
    parser = subparsers.add_parser(
        "train",
        help="train a LeRobot policy (ACT, diffusion) on a LeRobot export",
        description=(
            "Run LeRobot's own training (lerobot-train) on a dataset written by 'workcell "
            "export --format lerobot', offline, with defaults that train a state-only policy "
            "on a CPU in well under an hour. Writes LeRobot's standard checkpoint under "
            "OUT/checkpoints/last/pretrained_model and LeRobot's log in OUT/train.log; drive "
            "with it by 'workcell collect --operator policy:OUT'. Needs the learn extra "
            "(pip install 'workcell[learn]')."
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
        help="torch threads (default: one per core); 1 is fastest on a machine busy with "
        "other work",
    )
    parser.add_argument(
        "--save-every", type=int, metavar="N", help="also keep a checkpoint every N steps"
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
    from workcell.learn.train import run_training, train_command  # noqa: PLC0415
    from workcell.learn.train_options import TrainOptions  # noqa: PLC0415

    options = TrainOptions(
        dataset=args.dataset,
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
    print(f"training {options.policy} on {device} for {options.steps} steps; LeRobot's command:")
    print("  " + shlex.join(["lerobot-train", *command[3:]]), flush=True)
    bar = _ProgressBar()
    result = run_training(options, bar.show)
    bar.finish()
    loss = f", final loss {result.last.loss:.4g}" if result.last is not None else ""
    seed = evaluation_seed(args.dataset)
    print(
        f"trained in {result.seconds / 60:.1f} min{loss}\n"
        f"checkpoint: {result.checkpoint.path}\n"
        f"operator id: {result.checkpoint.operator_id}\n"
        f"evaluate it on worlds none of its demonstrations saw: workcell collect --operator "
        f"policy:{options.out} --mode collection --trials 200 --seed {seed}"
        " --store eval.sqlite, then workcell audit --store eval.sqlite --out report"
    )
    return 0


def evaluation_seed(dataset: Path) -> int:
    """The first seed from 1000 on that none of the dataset's sessions used (the export's
    provenance names them), so that an evaluation meets new worlds."""
    from workcell.export.lerobot_layout import PROVENANCE_JSON_PATH  # noqa: PLC0415

    try:
        provenance = json.loads((dataset / PROVENANCE_JSON_PATH).read_text())
        used = {int(session["seed"]) for session in provenance["sessions"].values()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        used = set()
    seed = 1000
    while seed in used:
        seed += 1
    return seed


class _ProgressBar:
    """One line, rewritten in place on a terminal; a line every 10 % otherwise."""

    WIDTH = 30

    def __init__(self) -> None:
        self.live = sys.stderr.isatty()
        self._shown_tenth = -1

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
        elif int(share * 10) > self._shown_tenth:
            self._shown_tenth = int(share * 10)
            print(text, file=sys.stderr, flush=True)

    def finish(self) -> None:
        if self.live:
            print(file=sys.stderr)
