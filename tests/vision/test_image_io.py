import numpy as np
import pytest
from PIL import Image

from pix2pockets.vision.image_io import decode_image_rgb, read_image_rgb


def test_reads_png_as_rgb(tmp_path):
    p = tmp_path / "a.png"
    Image.fromarray(np.full((4, 6, 3), 7, np.uint8)).save(p)
    img = read_image_rgb(p)
    assert img.shape == (4, 6, 3) and img.dtype == np.uint8 and img[0, 0, 0] == 7


def test_grey_png_becomes_three_channels(tmp_path):
    p = tmp_path / "g.png"
    Image.fromarray(np.zeros((3, 3), np.uint8)).save(p)
    assert read_image_rgb(p).shape == (3, 3, 3)


def test_errors(tmp_path):
    text = tmp_path / "x.jpg"
    text.write_text("not an image")
    with pytest.raises(ValueError, match="not an image"):
        read_image_rgb(text)
    with pytest.raises(ValueError, match="not found"):
        read_image_rgb(tmp_path / "missing.png")
    big = tmp_path / "big.png"
    Image.fromarray(np.zeros((40, 40, 3), np.uint8)).save(big)
    with pytest.raises(ValueError, match="too large"):
        read_image_rgb(big, max_pixels=100)
    full = tmp_path / "t.jpg"
    Image.fromarray(np.random.default_rng(0).integers(0, 255, (64, 64, 3), dtype=np.uint8)).save(full)
    cut = tmp_path / "cut.jpg"
    cut.write_bytes(full.read_bytes()[:300])
    with pytest.raises(ValueError, match="truncated"):
        read_image_rgb(cut)


def test_decode_bytes_matches_file_reading(tmp_path):
    p = tmp_path / "a.png"
    Image.fromarray(np.arange(48, dtype=np.uint8).reshape(4, 4, 3)).save(p)
    np.testing.assert_array_equal(decode_image_rgb(p.read_bytes()), read_image_rgb(p))


@pytest.mark.parametrize(
    ("data", "match"),
    [(b"", "photo.png is empty"), (b"hello", "not an image file: photo.png"), (b"\x89PNG\r\n\x1a\n\0\0", "photo.png")],
)
def test_decode_bytes_errors(data, match):
    with pytest.raises(ValueError, match=match):
        decode_image_rgb(data, "photo.png")


def test_exif_orientation_is_applied():
    import io

    pixels = np.zeros((2, 3, 3), np.uint8)
    pixels[0, 0] = 255  # top-left marker in the stored (sideways) image
    im = Image.fromarray(pixels)
    exif = im.getexif()
    exif[0x0112] = 6  # "rotate 90 degrees clockwise to display"
    buf = io.BytesIO()
    im.save(buf, format="PNG", exif=exif)
    rgb = decode_image_rgb(buf.getvalue())
    assert rgb.shape == (3, 2, 3)
    assert rgb[0, 1, 0] == 255  # the marker moved to the top-right corner


def test_a_phones_heic_photo_is_read(tmp_path):
    pillow_heif = pytest.importorskip("pillow_heif")
    pixels = np.zeros((48, 64, 3), np.uint8)
    pixels[:, :32] = (200, 40, 40)  # red left half, green right half
    pixels[:, 32:] = (30, 150, 60)
    path = tmp_path / "IMG_0001.HEIC"
    pillow_heif.from_pillow(Image.fromarray(pixels)).save(path, quality=95)  # written without Pillow's registry
    rgb = read_image_rgb(path)
    assert rgb.shape == (48, 64, 3) and rgb.dtype == np.uint8
    assert np.abs(rgb[:, 4:28].mean(axis=(0, 1)) - (200, 40, 40)).max() < 12
    assert np.abs(rgb[:, 36:60].mean(axis=(0, 1)) - (30, 150, 60)).max() < 12
    np.testing.assert_array_equal(decode_image_rgb(path.read_bytes(), "IMG_0001.HEIC"), rgb)


def test_capped_size_shrinks_only_what_is_too_long():
    from pix2pockets.vision.image_io import capped_size

    assert capped_size(640, 480, 1920) == (640, 480)
    assert capped_size(4032, 3024, 1920) == (1920, 1440)
    assert capped_size(3024, 4032, 1920) == (1440, 1920)
    assert capped_size(1137.8, 640.0, 4000) == (1138, 640)
    assert capped_size(10000, 2, 1000) == (1000, 1)
