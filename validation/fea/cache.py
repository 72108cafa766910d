"""A disk cache of FEA work that depends only on its inputs: meshes, unit-load solutions, direct peaks.

    cache = DiskCache(CacheSettings("/home/me/.cache/linkstress"))
    key = cache_key("mesh", {"region": ..., "settings": ...})
    arrays = cache.load("mesh", key)  # None on a miss (or a damaged entry)
    cache.store("mesh", key, {"p": ..., "t": ...})

An entry is a NumPy ``.npz`` of plain arrays (read with ``allow_pickle=False``: nothing in it runs
code), in ``DIRECTORY/KIND/KEY.npz``. Its key is the SHA-256 of a canonical serialisation of
everything that determines it (``cache_key``: JSON of plain values, floats in hexadecimal, arrays by
the hash of their bytes), with the cache format, the sparse solver, this package's version, the
versions of the libraries that compute it and a hash of the FEA engine's own source files, so that
changed code never reads an entry it did not write.

- Written atomically: to a temporary file in the same folder, then ``os.replace``d into place, so a
  reader sees a whole entry or none, and two processes writing one key at once both leave a whole
  one (the same one: the same inputs give the same arrays).
- Verified on read: each entry holds its key and a SHA-256 over its arrays' names, types, shapes
  and bytes; one that does not open, or whose checksum or key does not match (truncated, flipped
  bits), is deleted and counts as a miss, never trusted.
- Bounded: after each write, the least recently used entries (by modification time, which a read
  renews) are deleted until the folder holds at most ``max_bytes``; temporary files a killed
  process left are deleted after an hour.

The cache only saves time: any failure to write (a full disk, a read-only folder) leaves the run's
results as they are.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import math
import os
import tempfile
import time
import zipfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from linkstress.validation.fea.errors import FEAError

FORMAT = 1
"""The entries' layout; raised when it changes, so that old entries are never read."""
CACHE_VARIABLE = "LINKSTRESS_CACHE"
"""Environment variable: the cache's folder (``--cache DIR`` overrides it)."""
SIZE_VARIABLE = "LINKSTRESS_CACHE_SIZE"
"""Environment variable: the cache's largest size in bytes (e.g. ``5e8``); default DEFAULT_MAX_BYTES."""
DEFAULT_MAX_BYTES = 2_000_000_000
STALE_TEMPORARY_SECONDS = 3600.0
"""A temporary file this old was left by a process that died while writing it."""
CHECKSUM = "checksum__"
KEY = "key__"
LIBRARIES = ("numpy", "scipy", "scikit-fem", "gmsh", "scikit-sparse")
"""Libraries whose version is part of every key (absent ones count as absent)."""
CORE_SOURCES = ("linkstress.loads", "linkstress.stress_state")
"""Modules outside the FEA engine whose code shapes what is cached (the body-load terms of
``LinkLoadCase.body_force_density``, the von Mises of a direct peak): their source is hashed too."""


@dataclass(frozen=True)
class CacheSettings:
    """Where the cache is (``directory``, an absolute path) and how large it may grow [bytes]. Plain
    data: it travels with a task to the process or Dask worker that runs it."""

    directory: str
    max_bytes: int = DEFAULT_MAX_BYTES


@dataclass(frozen=True)
class DiskCache:
    """The cache of ``settings``; see the module's docstring."""

    settings: CacheSettings

    @property
    def folder(self) -> Path:
        return Path(self.settings.directory)

    def path(self, kind: str, key: str) -> Path:
        return self.folder / kind / f"{key}.npz"

    def load(self, kind: str, key: str) -> dict[str, NDArray] | None:
        """The arrays stored under ``key``, or None when there are none or they are damaged (a
        damaged entry is deleted). A hit renews the entry's place in the least-recently-used order."""
        path = self.path(kind, key)
        try:
            with np.load(path, allow_pickle=False) as entry:
                arrays = {name: entry[name] for name in entry.files}
        except FileNotFoundError:
            return None
        except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
            _remove(path)
            return None
        checksum, stored_key = arrays.pop(CHECKSUM, None), arrays.pop(KEY, None)
        if (
            checksum is None or stored_key is None
            or checksum.tobytes() != _checksum(arrays) or stored_key.tobytes() != key.encode()
        ):
            _remove(path)
            return None
        try:
            os.utime(path)
        except OSError:
            pass
        return arrays

    def store(self, kind: str, key: str, arrays: dict[str, NDArray]) -> None:
        """Write ``arrays`` (plain numeric or string arrays; no objects) under ``key``, atomically,
        then keep the cache within its size. A failure to write is ignored: the cache only saves time."""
        arrays = {name: np.ascontiguousarray(value) for name, value in arrays.items()}
        if any(a.dtype.hasobject for a in arrays.values()):
            raise FEAError("the FEA cache stores plain arrays only, not Python objects")
        size = sum(a.nbytes for a in arrays.values())
        if size > self.settings.max_bytes:
            return
        arrays[CHECKSUM] = np.frombuffer(_checksum(arrays), dtype=np.uint8)
        arrays[KEY] = np.frombuffer(key.encode(), dtype=np.uint8)
        path = self.path(kind, key)
        temporary = None
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=".", suffix=".tmp")
            with os.fdopen(handle, "wb") as file:
                np.savez(file, **arrays)
            os.replace(temporary, path)
        except OSError:
            if temporary is not None:
                _remove(Path(temporary))
            return
        self.evict()

    def evict(self) -> None:
        """Delete the least recently used entries until the cache holds at most ``max_bytes``, and
        temporary files older than STALE_TEMPORARY_SECONDS."""
        entries, total, now = [], 0, time.time()
        for path in self.folder.glob("*/*"):
            try:
                stat = path.stat()
            except OSError:
                continue
            if path.suffix == ".tmp":
                if now - stat.st_mtime > STALE_TEMPORARY_SECONDS:
                    _remove(path)
                    continue
            elif path.suffix != ".npz":
                continue
            else:
                entries.append((stat.st_mtime, path, stat.st_size))
            total += stat.st_size
        for _, path, size in sorted(entries, key=lambda e: e[0]):
            if total <= self.settings.max_bytes:
                break
            _remove(path)
            total -= size

    def size(self) -> int:
        """Bytes the cache's entries take (an entry another process deletes meanwhile counts as none)."""
        total = 0
        for path in self.folder.glob("*/*.npz"):
            try:
                total += path.stat().st_size
            except OSError:
                pass
        return total


def _remove(path: Path) -> None:
    try:
        path.unlink()
    except OSError:
        pass


def _checksum(arrays: dict[str, NDArray]) -> bytes:
    """SHA-256 over each array's name, type, shape and bytes, in name order."""
    digest = hashlib.sha256()
    for name in sorted(arrays):
        value = arrays[name]
        digest.update(json.dumps([name, value.dtype.str, value.shape]).encode())
        digest.update(np.ascontiguousarray(value).reshape(-1).view(np.uint8))
    return digest.digest()


def cache_key(kind: str, parts: dict) -> str:
    """SHA-256 (hex) of ``kind``, ``parts`` and the code's fingerprint, serialised canonically:
    dicts with sorted string keys, lists, strings, booleans, integers, None, floats exactly (in
    hexadecimal) and arrays by dtype, shape and the SHA-256 of their bytes. Anything else is a
    programming error (TypeError): no object is pickled into a key."""
    from linkstress.validation.fea.plane_stress import spd_solver  # it imports the mesh, which imports this

    return key_of(kind, parts, spd_solver())


def key_of(kind: str, parts: dict, solver: str) -> str:
    """``cache_key`` with the sparse ``solver`` named by the caller: for a key made before the FEA
    stack is imported (``linkstress.validation.peaks_scene``'s stored sweeps)."""
    document = {"kind": kind, "format": FORMAT, "code": code_fingerprint(), "solver": solver, "parts": parts}
    text = json.dumps(_canonical(document), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _canonical(value):
    if isinstance(value, dict):
        if not all(isinstance(k, str) for k in value):
            raise TypeError(f"cache keys take string-keyed dicts, got keys {list(value)!r}")
        return {k: _canonical(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        number = float(value)
        return {"float": number.hex() if math.isfinite(number) else repr(number)}
    if isinstance(value, np.ndarray):
        array = np.ascontiguousarray(value)
        if array.dtype.hasobject:
            raise TypeError("cache keys take numeric arrays, not object arrays")
        return {"array": array.dtype.str, "shape": list(array.shape),
                "sha256": hashlib.sha256(array.reshape(-1).view(np.uint8)).hexdigest()}
    raise TypeError(f"cache keys take plain values and arrays, not {type(value).__name__}")


@lru_cache(maxsize=1)
def code_fingerprint() -> dict:
    """This package's version, the versions of the libraries the FEA uses, and the SHA-256 of the
    FEA engine's source files and CORE_SOURCES' (an editable install changes them, not its version)."""
    import importlib.metadata  # tens of ms to import: once, where a key is made

    from linkstress import __version__

    versions = {}
    for name in LIBRARIES:
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            versions[name] = None
    paths = sorted(Path(__file__).resolve().parent.glob("*.py"))
    paths += [Path(importlib.util.find_spec(name).origin) for name in CORE_SOURCES]
    sources = hashlib.sha256()
    for path in paths:
        sources.update(path.name.encode() + b"\0" + path.read_bytes())
    return {"linkstress": __version__, "libraries": versions, "sources": sources.hexdigest()}


def cache_settings(directory: str | os.PathLike | None, off: bool = False) -> CacheSettings | None:
    """The cache a command uses: none when ``off`` (``--no-cache``); else in ``directory``
    (``--cache DIR``), else in ``LINKSTRESS_CACHE``, else in the user's cache folder (platformdirs),
    of at most ``LINKSTRESS_CACHE_SIZE`` bytes. FEAError (an InputError) for a size that is not a
    number of bytes, or a folder that cannot be made or is not a folder."""
    if off:
        return None
    size_text = os.environ.get(SIZE_VARIABLE, "").strip()
    max_bytes = DEFAULT_MAX_BYTES
    if size_text:
        try:
            max_bytes = float(size_text)
        except ValueError:
            max_bytes = math.nan
        if not (math.isfinite(max_bytes) and max_bytes >= 0):
            raise FEAError(f"{SIZE_VARIABLE}: {size_text!r} is not a size in bytes; give e.g. 2e9 (2 GB), or unset it")
    if directory is not None:
        folder, source = Path(directory), "--cache"
    elif os.environ.get(CACHE_VARIABLE, "").strip():
        folder, source = Path(os.environ[CACHE_VARIABLE].strip()), CACHE_VARIABLE
    else:
        import platformdirs  # 40 ms to import: only when a cache is used

        folder, source = Path(platformdirs.user_cache_dir("linkstress", appauthor=False)), "the user's cache folder"
    folder = folder.expanduser().absolute()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise FEAError(
            f"{source}: cannot make the cache folder {str(folder)!r} ({error.strerror or error}); give another with "
            "--cache DIR, or run with --no-cache"
        ) from None
    return CacheSettings(str(folder), int(max_bytes))


def open_cache(settings: CacheSettings | None) -> DiskCache | None:
    """The cache of ``settings`` (None: no cache)."""
    return None if settings is None else DiskCache(settings)
