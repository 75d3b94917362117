"""The secret that signs a store's chain (``--key FILE``)."""

from __future__ import annotations

import hashlib
import hmac
from dataclasses import dataclass
from pathlib import Path

from workcell.record.errors import StoreError

MIN_KEY_BYTES = 16


@dataclass(frozen=True, repr=False)
class ChainKey:
    """The secret that signs chain heads; :attr:`key_id` names it publicly."""

    secret: bytes

    @classmethod
    def from_file(cls, path: str | Path) -> ChainKey:
        """The key in ``path`` (its bytes, surrounding white space removed)."""
        try:
            secret = Path(path).read_bytes().strip()
        except OSError as error:
            raise StoreError(
                f"key file {path}: cannot be read ({error.strerror or error})"
            ) from None
        if len(secret) < MIN_KEY_BYTES:
            raise StoreError(
                f"key file {path}: holds {len(secret)} bytes; a key needs at least "
                f"{MIN_KEY_BYTES} (make one: python -c 'import secrets; "
                f"print(secrets.token_hex(32))' > {path})"
            )
        return cls(secret)

    @property
    def key_id(self) -> str:
        """16 hex digits that tell keys apart without revealing them."""
        return hashlib.sha256(b"workcell/key-id/v1\0" + self.secret).hexdigest()[:16]

    def sign(self, head: str) -> str:
        return hmac.new(self.secret, head.encode(), hashlib.sha256).hexdigest()

    def __repr__(self) -> str:
        return f"ChainKey({self.key_id})"
