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


def test_two_writers_of_one_file_do_not_share_a_temporary(tmp_path):
    """Interleaved writers (two processes writing the same output): each has its own temporary, the last rename
    wins, both complete."""
    target = tmp_path / "o.nc"
    with replacing(target) as first, replacing(target) as second:
        assert first != second and first.parent == second.parent == tmp_path
        first.write_text("first")
        second.write_text("second")
    assert target.read_text() == "first"  # the outer block ends last
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.nc"]


def test_a_written_file_has_the_permissions_of_a_new_file(tmp_path):
    """Result files are shared (a group's results directory): readable as a plainly created file, not private."""
    import os

    old = os.umask(0o022)
    try:
        with replacing(tmp_path / "case.nc") as tmp:
            tmp.write_text("x")
        (tmp_path / "plain.txt").write_text("x")
    finally:
        os.umask(old)
    assert (tmp_path / "case.nc").stat().st_mode & 0o777 == (tmp_path / "plain.txt").stat().st_mode & 0o777 == 0o644
