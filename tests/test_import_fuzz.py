"""Fuzzing both readers: random bytes, truncated and corrupted files give a Sketch or a SketchError,
never another exception."""

from __future__ import annotations

import ezdxf
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from linkstress.errors import SketchError
from linkstress.importers import read_sketch
from test_import_csv import old_rule_rows, v1_rows
from test_import_dxf import draw, plate_entities

FUZZ = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


class Files(dict):
    """Valid sketch files by kind (a short repr keeps hypothesis' reports readable)."""

    def __repr__(self) -> str:
        return f"Files({sorted(self)})"


@pytest.fixture(scope="module")
def valid(folder):
    doc = ezdxf.new("R2013", units=4)
    draw(doc.modelspace(), plate_entities(), layer="plate")
    doc.saveas(folder / "plate.dxf")
    rows, _, _ = old_rule_rows()
    return Files({
        "dxf": (folder / "plate.dxf").read_bytes(),
        "old csv": ("\r\n".join(rows) + "\r\n").encode(),
        "v1 csv": ("\n".join(v1_rows()) + "\n").encode(),
    })


def read_only_sketch_errors(path, data: bytes) -> None:
    path.write_bytes(data)
    try:
        read_sketch(path)
    except SketchError as error:
        assert str(error).startswith(path.name + ": ") and "\n" not in str(error)


@FUZZ
@given(data=st.binary(max_size=3000), suffix=st.sampled_from([".dxf", ".csv", ".sketch"]))
def test_random_bytes_give_only_sketch_errors(folder, data, suffix):
    read_only_sketch_errors(folder / f"random{suffix}", data)


@FUZZ
@given(kind=st.sampled_from(["dxf", "old csv", "v1 csv"]), fraction=st.floats(0, 1))
def test_truncated_files_give_a_sketch_or_a_sketch_error(folder, valid, kind, fraction):
    data = valid[kind]
    suffix = ".dxf" if kind == "dxf" else ".csv"
    read_only_sketch_errors(folder / f"cut{suffix}", data[:int(fraction * len(data))])


@FUZZ
@given(kind=st.sampled_from(["dxf", "old csv", "v1 csv"]), fraction=st.floats(0, 1), byte=st.integers(0, 255))
def test_corrupted_files_give_a_sketch_or_a_sketch_error(folder, valid, kind, fraction, byte):
    data = bytearray(valid[kind])
    data[min(int(fraction * len(data)), len(data) - 1)] = byte
    suffix = ".dxf" if kind == "dxf" else ".csv"
    read_only_sketch_errors(folder / f"corrupt{suffix}", bytes(data))
