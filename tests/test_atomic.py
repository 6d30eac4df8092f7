"""Atomic writes: the target appears only complete; a failed write leaves nothing."""

import pytest

from capslide.io.atomic import replacing


def test_replacing_renames_on_success_and_cleans_up_on_failure(tmp_path):
    target = tmp_path / "sub" / "out.txt"
    with replacing(target) as tmp:
        tmp.write_text("new")
        assert not target.exists()  # nothing at the target while writing
    assert target.read_text() == "new"
    with pytest.raises(RuntimeError):
        with replacing(target) as tmp:
            tmp.write_text("half")
            raise RuntimeError("killed")
    assert target.read_text() == "new" and sorted(p.name for p in target.parent.iterdir()) == ["out.txt"]
