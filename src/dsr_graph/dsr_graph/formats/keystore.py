"""The DSR keystore, in the spirit of SROS2's: one folder, one enclave per node.

    DIR/                         0700
      keystore.json              {"format": "dsr-keystore", "version": 1, "server": "/dsr_server"}
      enclaves/<node name>/      0700, one per fully qualified node name (/ns/speech: ns/speech)
        key.pem                  the node's Ed25519 private key (PKCS#8 PEM), 0600
        public.pem               its public key (SubjectPublicKeyInfo PEM)

``dsr keystore init DIR [--server NAME]`` makes it with the DSR server's enclave;
``dsr keystore add DIR /node_name`` adds a node's. A node signs with its own ``key.pem``; every
process verifies with all the ``public.pem`` (a message is the server's only if the server's key
signed it). Every process of the suite reads the same folder (``DSR_KEYSTORE``): on one machine,
or copied to both hosts. The private keys are protected by file modes only: root on the host,
or the user running the suite, can read them (as SROS2's).
"""

from __future__ import annotations

import json
import os
import re
from dataclasses import dataclass
from pathlib import Path

from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from dsr_graph.exceptions import KeystoreError
from dsr_graph.formats.private_files import private_dir, write_private
from dsr_graph.formats.safe_json import loads_object

FORMAT, VERSION = "dsr-keystore", 1
META = "keystore.json"
ENCLAVES = "enclaves"
PRIVATE, PUBLIC = "key.pem", "public.pem"
DEFAULT_SERVER = "/dsr_server"
# a ROS fully qualified node name: /[namespace/]name, tokens of letters, digits and underscores
NODE_NAME = re.compile(r"^(/[A-Za-z_][A-Za-z0-9_]*)+$")


def check_name(name: str) -> str:
    if not NODE_NAME.match(name):
        raise KeystoreError(
            f"{name!r} is not a fully qualified node name (/name or /namespace/name: letters, "
            "digits and underscores)"
        )
    return name


@dataclass(frozen=True)
class Keystore:
    root: Path
    server: str  # the DSR server's fully qualified name: only its key signs the DSR's stream

    @classmethod
    def open(cls, root: os.PathLike | str) -> Keystore:
        root = Path(root)
        meta = root / META
        try:
            doc = loads_object(meta.read_bytes(), 64 * 1024)
        except OSError as e:
            raise KeystoreError(
                f"{root} is not a keystore ({meta}: {e.strerror}); make one with "
                f"dsr keystore init {root}"
            ) from None
        except ValueError as e:
            raise KeystoreError(f"{meta}: {e}") from None
        if doc.get("format") != FORMAT or doc.get("version") != VERSION:
            raise KeystoreError(f'{meta}: not a {FORMAT} version {VERSION} ("format", "version")')
        server = doc.get("server")
        if not isinstance(server, str):
            raise KeystoreError(f'{meta}: "server" must be the DSR server\'s node name')
        return cls(root, check_name(server))

    @classmethod
    def init(cls, root: os.PathLike | str, server: str = DEFAULT_SERVER) -> tuple[Keystore, bool]:
        """A keystore at ``root`` with the server's enclave; (keystore, made now). An existing
        keystore is kept as it is (its keys stay valid) when it names the same server."""
        root = Path(root)
        check_name(server)
        if (root / META).exists():
            existing = cls.open(root)
            if existing.server != server:
                raise KeystoreError(
                    f"{root} is a keystore for the server {existing.server!r}, not {server!r}"
                )
            existing.add(server)
            return existing, False
        private_dir(root)
        private_dir(root / ENCLAVES)
        meta = json.dumps({"format": FORMAT, "version": VERSION, "server": server}) + "\n"
        write_private(root / META, meta.encode())
        keystore = cls(root, server)
        keystore.add(server)
        return keystore, True

    def enclave(self, name: str) -> Path:
        return self.root / ENCLAVES / check_name(name).lstrip("/")

    def add(self, name: str) -> bool:
        """Give ``name`` a key pair; False if it has one already (kept: rotating a key is a
        remove and an add, on purpose)."""
        folder = self.enclave(name)
        if (folder / PRIVATE).exists():
            return False
        private_dir(folder)
        key = Ed25519PrivateKey.generate()
        pem = key.private_bytes(
            serialization.Encoding.PEM,
            serialization.PrivateFormat.PKCS8,
            serialization.NoEncryption(),
        )
        public = key.public_key().public_bytes(
            serialization.Encoding.PEM, serialization.PublicFormat.SubjectPublicKeyInfo
        )
        write_private(folder / PUBLIC, public)
        write_private(folder / PRIVATE, pem)  # written last: its presence means complete
        return True

    def names(self) -> list[str]:
        base = self.root / ENCLAVES
        return sorted("/" + str(p.parent.relative_to(base)) for p in base.rglob(PUBLIC))

    def private_key(self, name: str) -> Ed25519PrivateKey | None:
        """``name``'s private key, None if the keystore has no enclave for it."""
        path = self.enclave(name) / PRIVATE
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            return None
        except OSError as e:
            raise KeystoreError(f"cannot read {path}: {e.strerror}") from None
        key = serialization.load_pem_private_key(data, password=None)
        if not isinstance(key, Ed25519PrivateKey):
            raise KeystoreError(f"{path} is not an Ed25519 private key")
        return key

    def public_keys(self) -> dict[str, Ed25519PublicKey]:
        keys = {}
        for name in self.names():
            path = self.enclave(name) / PUBLIC
            key = serialization.load_pem_public_key(path.read_bytes())
            if not isinstance(key, Ed25519PublicKey):
                raise KeystoreError(f"{path} is not an Ed25519 public key")
            keys[name] = key
        return keys
