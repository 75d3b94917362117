"""What ``workcell train`` asks of LeRobot, with defaults that work offline on a CPU.

The defaults train a state-only policy (``observation.state`` and
``observation.environment_state``; no images, so no backbone weights to download) small
enough to learn the box transfer in well under an hour on a 2-core machine without a GPU.
Each is a LeRobot option; :func:`lerobot_arguments` spells them as ``lerobot-train``'s
command line, so a run can be repeated with LeRobot alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

from workcell.errors import ConfigError

PolicyType = Literal["act", "diffusion"]
POLICY_TYPES: tuple[PolicyType, ...] = ("act", "diffusion")
Device = Literal["auto", "cpu", "cuda"]
DEVICES: tuple[Device, ...] = ("auto", "cpu", "cuda")

DEFAULT_THREADS = 1
"""One torch thread, beside one data-loading worker: what bench/learn.py and the published
timings use. Torch's own default, a thread per core, crawls on a machine busy with other
work (3-13 s per step on a shared 2-core machine against 1.2-2.3 s with one thread;
measured again with the default ACT: 2.9 and 5.3 s a step at loads 3-8 and 7-12 against
0.34 and 0.53 s at loads 1-3 and 7, with 5 times the CPU time: threads that spin waiting
for each other on a shared core); more pay only on idle cores (README.md)."""
CHECKPOINTS_PER_RUN = 10
"""Without --save-every: a checkpoint every tenth of the steps."""
LOG_LINES_EVERY = 10
"""At most this many steps between LeRobot's log lines (the progress the user sees)."""

POLICY_DEFAULTS: dict[PolicyType, dict[str, str]] = {
    "act": {
        # a small transformer: ~4 steps/s with batch 32 on a quiet 2-core CPU (one data worker)
        "dim_model": "256",
        "dim_feedforward": "1024",
        "n_encoder_layers": "2",
        "n_decoder_layers": "1",
        "n_vae_encoder_layers": "2",
        # half a second of actions at the 20 Hz frame rate, all executed before the next
        # call: against one second (20) the same 50 DART demonstrations of D1 went from
        # 45/50 and 88/100 to 49/50 and 99/100 (bench/README.md, bench/learn_d1.py)
        "chunk_size": "10",
        "n_action_steps": "10",
        "optimizer_lr": "1e-4",
        "pretrained_backbone_weights": "null",
    },
    "diffusion": {
        "down_dims": "[128,256,512]",
        "horizon": "16",
        "n_action_steps": "8",
        "n_obs_steps": "2",
        "noise_scheduler_type": "DDIM",
        "num_inference_steps": "10",
        "pretrained_backbone_weights": "null",
    },
}
"""LeRobot policy options that differ from LeRobot's own defaults, per policy type."""


@dataclass(frozen=True)
class TrainOptions:
    dataset: Path
    """A LeRobotDataset v3.0 directory (``workcell export --format lerobot``)."""
    out: Path
    """Where LeRobot writes its checkpoints (must not exist, or be empty)."""
    policy: PolicyType = "act"
    steps: int = 10_000
    batch_size: int = 32
    episodes: tuple[int, ...] | None = None
    """Train on these episode indices only (None: every episode)."""
    device: Device = "auto"
    seed: int = 1000
    save_every: int | None = None
    """Steps between checkpoints, every one kept. None: a checkpoint every tenth of the
    steps (:attr:`checkpoint_every`), only the newest kept, so that a run cut short leaves
    a policy to drive with."""
    threads: int = DEFAULT_THREADS
    """Torch (OpenMP) threads of the training process (see :data:`DEFAULT_THREADS`); 0:
    torch's own default, a thread per core."""
    num_workers: int = 1
    """Data-loading processes (0: in the training process). One worker overlaps LeRobot's
    loading of each batch (a third of a step here: its query of the action chunks)
    with the model's update: 1.5x the steps per second on a quiet 2-core machine
    (bench/README.md)."""
    extra: tuple[str, ...] = field(default_factory=tuple)
    """Further ``--key=value`` options for ``lerobot-train``, after the defaults."""

    def __post_init__(self) -> None:
        problems = []
        if self.policy not in POLICY_TYPES:
            problems.append(f"--policy = {self.policy!r}: must be one of {', '.join(POLICY_TYPES)}")
        if type(self.steps) is not int or not 1 <= self.steps <= 10_000_000:
            problems.append(f"--steps = {self.steps!r}: must be 1 to 10000000")
        if type(self.batch_size) is not int or not 1 <= self.batch_size <= 65_536:
            problems.append(f"--batch-size = {self.batch_size!r}: must be 1 to 65536")
        if self.episodes is not None and (
            not self.episodes or any(type(e) is not int or e < 0 for e in self.episodes)
        ):
            problems.append(
                f"--episodes = {self.episodes!r}: must be episode indices (0, 1, ...), at least one"
            )
        if self.device not in DEVICES:
            problems.append(f"--device = {self.device!r}: must be one of {', '.join(DEVICES)}")
        if self.save_every is not None and not 1 <= self.save_every <= self.steps:
            problems.append(f"--save-every = {self.save_every!r}: must be 1 to --steps")
        if type(self.threads) is not int or not 0 <= self.threads <= 1024:
            problems.append(f"--threads = {self.threads!r}: must be 0 (torch's own) to 1024")
        if not 0 <= self.num_workers <= 64:
            problems.append(f"--num-workers = {self.num_workers!r}: must be 0 to 64")
        bad = [e for e in self.extra if not (e.startswith("--") and "=" in e)]
        if bad:
            problems.append(
                f"--lerobot {bad[0]!r}: must be --key=value, e.g. --policy.dim_model=512"
            )
        if problems:
            raise ConfigError(problems)

    @property
    def job_name(self) -> str:
        return self.out.name or "workcell"

    @property
    def checkpoint_every(self) -> int:
        """Steps between checkpoints: ``save_every``, else a tenth of the run."""
        return self.save_every or math.ceil(self.steps / CHECKPOINTS_PER_RUN)

    @property
    def log_every(self) -> int:
        """Steps between LeRobot's log lines: every :data:`LOG_LINES_EVERY` steps at most
        (every step of a short run), unless ``--lerobot=--log_freq=N`` says otherwise."""
        given = [e.partition("=")[2] for e in self.extra if e.startswith("--log_freq=")]
        if given and given[-1].isdigit() and int(given[-1]) > 0:
            return int(given[-1])
        return max(1, min(LOG_LINES_EVERY, math.ceil(self.steps / 100)))


def lerobot_arguments(options: TrainOptions, device: str, has_videos: bool) -> list[str]:
    """``lerobot-train``'s arguments for ``options`` on ``device``."""
    policy = options.policy
    arguments = [
        f"--dataset.repo_id=local/{options.dataset.name or 'dataset'}",
        f"--dataset.root={options.dataset}",
        f"--policy.type={policy}",
        f"--policy.device={device}",
        "--policy.push_to_hub=false",
        *(f"--policy.{key}={value}" for key, value in POLICY_DEFAULTS[policy].items()),
        f"--output_dir={options.out}",
        f"--job_name={options.job_name}",
        f"--steps={options.steps}",
        f"--batch_size={options.batch_size}",
        f"--save_freq={options.checkpoint_every}",
        f"--log_freq={options.log_every}",
        f"--num_workers={options.num_workers}",
        f"--seed={options.seed}",
        "--eval_freq=0",
        "--wandb.enable=false",
    ]
    if options.episodes is not None:
        arguments.append(f"--dataset.episodes=[{','.join(map(str, options.episodes))}]")
    if has_videos:
        # torchcodec needs the system's FFmpeg libraries; PyAV brings its own
        arguments.append("--dataset.video_backend=pyav")
    return [*arguments, *options.extra]
