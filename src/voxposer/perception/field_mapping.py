"""Dict-style read access to a frozen dataclass's fields (``obj["position"]``).

Language model programs written for the paper index detected objects like dicts; our objects are
typed dataclasses. Subclasses name the readable fields in ``keys``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any, ClassVar


class FieldMapping(Mapping[str, Any]):
    """A read-only mapping over the attributes listed in ``keys``."""

    keys_: ClassVar[tuple[str, ...]] = ()
    noun: ClassVar[str] = "an object"

    def __getitem__(self, key: str) -> Any:
        if key not in self.keys_:
            raise KeyError(f"{key!r}; {self.noun} has: {', '.join(self.keys_)}")
        return getattr(self, key)

    def __iter__(self) -> Iterator[str]:
        return iter(self.keys_)

    def __len__(self) -> int:
        return len(self.keys_)
