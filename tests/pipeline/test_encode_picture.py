import cv2
import numpy as np
import pytest

from pix2pockets.pipeline.draw import encode_picture


@pytest.mark.parametrize(("suffix", "fast"), [(".png", False), (".png", True), (".jpg", False), (".JPEG", False)])
def test_encode_round_trip_keeps_rgb_order(suffix, fast):
    rgb = np.zeros((16, 24, 3), np.uint8)
    rgb[..., 0] = 200  # red
    data = encode_picture(rgb, suffix, fast=fast)
    back = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)[:, :, ::-1]
    assert back.shape == rgb.shape
    assert abs(int(back[..., 0].mean()) - 200) <= 3 and back[..., 2].mean() < 5


def test_encode_rejects_unknown_type():
    with pytest.raises(ValueError, match=r"use \.png or \.jpg"):
        encode_picture(np.zeros((4, 4, 3), np.uint8), ".gif")
