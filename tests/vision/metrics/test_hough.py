import cv2
import numpy as np

from pix2pockets.vision.metrics.hough import HoughDetector


def test_hough_finds_big_balls_not_small_when_diamonds_off():
    img = np.full((200, 300, 3), (20, 120, 60), np.uint8)
    for x in (60, 150, 240):
        cv2.circle(img, (x, 100), 20, (240, 240, 240), -1, cv2.LINE_AA)
    det = HoughDetector(diamonds=False).detect(img)
    assert len(det) >= 3
    centres = det.centres[det.confidence > 0.5]
    for x in (60, 150, 240):
        assert np.min(np.hypot(centres[:, 0] - x, centres[:, 1] - 100)) < 4
    assert not det.is_diamond.any()
