"""A LeRobot pretrained-policy directory: where it is, which policy, which weights.

``lerobot-train`` (and ``workcell train``) writes ``OUT/checkpoints/<step>/pretrained_model``
with ``config.json`` (the policy's type and features), ``model.safetensors`` (the weights)
and the policy's processor pipelines. A checkpoint can be named by that directory, by its
``checkpoints/<step>`` parent, or by the training output ``OUT`` (its last checkpoint).
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import dataclass
from pathlib import Path

from workcell.learn.errors import LearnError

CONFIG_FILE = "config.json"
WEIGHTS_FILE = "model.safetensors"
PRETRAINED_DIR = "pretrained_model"
LAST_CHECKPOINT = Path("checkpoints") / "last" / PRETRAINED_DIR
MAX_OPERATOR_ID = 64


@dataclass(frozen=True)
class PolicyCheckpoint:
    path: Path
    """The pretrained-model directory (``config.json``, ``model.safetensors``)."""
    policy_type: str
    """LeRobot's policy type: ``act``, ``diffusion``, ..."""
    weights_sha256: str
    name: str
    """The training run's name: its output directory's name."""

    @classmethod
    def locate(cls, given: str | Path) -> PolicyCheckpoint:
        """The checkpoint ``given`` names (see the module docstring)."""
        root = Path(given)
        candidates = (root, root / PRETRAINED_DIR, root / LAST_CHECKPOINT)
        found = next((c for c in candidates if (c / CONFIG_FILE).is_file()), None)
        if found is None:
            raise LearnError(
                f"policy {str(given)!r}: no LeRobot pretrained model there; give the directory "
                f"holding {CONFIG_FILE} and {WEIGHTS_FILE} (.../pretrained_model), or a "
                "training output directory (its checkpoints/last is used)"
            )
        weights = found / WEIGHTS_FILE
        if not weights.is_file():
            raise LearnError(f"policy {str(found)!r}: {WEIGHTS_FILE} is missing")
        try:
            policy_type = str(json.loads((found / CONFIG_FILE).read_text())["type"])
        except (OSError, ValueError, KeyError, TypeError) as error:
            raise LearnError(
                f"policy {str(found)!r}: {CONFIG_FILE} is not a LeRobot policy config ({error})"
            ) from None
        return cls(found.resolve(), policy_type, _sha256(weights), _run_name(found.resolve()))

    @property
    def operator_id(self) -> str:
        """``policy-<type>-<run>-<first 12 hex digits of the weights' SHA-256>``: the operator id
        its sessions are recorded under (letters, digits, '.', '_', '-'; at most 64). A run
        named after its type (``--out act``, ``act-200``) does not repeat it:
        ``policy-act-<digest>``, ``policy-act-200-<digest>``."""
        digest = self.weights_sha256[:12]
        kind = _clean(self.policy_type)
        head = f"policy-{kind}"
        room = MAX_OPERATOR_ID - len(head) - len(digest) - 2
        run = _without_prefix(_clean(self.name), kind)[:room]
        return f"{head}-{run}-{digest}" if run else f"{head}-{digest}"


def _run_name(pretrained: Path) -> str:
    """``OUT``'s name for ``OUT/checkpoints/<step>/pretrained_model``, else the folder's."""
    parts = pretrained.parts
    if len(parts) >= 4 and parts[-1] == PRETRAINED_DIR and parts[-3] == "checkpoints":
        return parts[-4]
    return pretrained.name


def _without_prefix(run: str, kind: str) -> str:
    """``run`` less a leading ``kind`` that stands alone (``act``, ``act-200``, ``ACT_1``;
    not ``actor``)."""
    if run.lower() == kind.lower():
        return ""
    if run[: len(kind)].lower() == kind.lower() and run[len(kind) : len(kind) + 1] in "-_.":
        return run[len(kind) :].lstrip("-_.")
    return run


def _clean(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("_")


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()
