"""The table fit's error messages: counts read right in the singular and the plural, lengths in the photo's pixels."""

import pytest

from pix2pockets.vision.table.errors import TableFitError, counted, in_photo_px, photo_pixels


def test_counted_names_one_thing_in_the_singular():
    assert counted(1, "cushion") == "1 cushion"
    assert [counted(n, "diamond") for n in (0, 2)] == ["0 diamonds", "2 diamonds"]


def test_lengths_in_messages_are_the_photos_pixels_where_a_copy_is_fitted():
    assert in_photo_px(12.34) == "12.3 px"
    assert in_photo_px(1234.0) == "1234 px"
    with photo_pixels(2.1):  # a 4032 px photo fitted on a 1920 px copy
        assert in_photo_px(10.0) == "21.0 px"
        with pytest.raises(TableFitError, match=r"\(error 21.0 px\)"):
            raise TableFitError(f"no table found (error {in_photo_px(10.0)})")
    assert in_photo_px(10.0) == "10.0 px"  # the scale ends with the block


def test_the_scale_ends_with_the_block_when_the_fit_raises():
    with pytest.raises(TableFitError), photo_pixels(3.0):
        raise TableFitError("no table found")
    assert in_photo_px(1.0) == "1.0 px"
