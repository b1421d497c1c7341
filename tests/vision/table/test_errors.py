"""Counts in the table fit's error messages read right in the singular and the plural."""

from pix2pockets.vision.table.errors import counted


def test_counted_names_one_thing_in_the_singular():
    assert counted(1, "cushion") == "1 cushion"
    assert [counted(n, "diamond") for n in (0, 2)] == ["0 diamonds", "2 diamonds"]
