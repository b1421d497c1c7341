"""Table boxes of ball-only photos: points on / off the table, and diamonds counted off it."""

import numpy as np

from pix2pockets.vision.detect.detections import Detections
from pix2pockets.vision.metrics.evaluation import diamonds_off_table
from pix2pockets.vision.metrics.table_box import inside_table_boxes


def test_inside_widened_boxes():
    boxes = np.array([[100.0, 100.0, 200.0, 150.0]])
    pts = np.array([[150.0, 120.0], [99.0, 120.0], [90.0, 120.0], [150.0, 151.5], [300.0, 300.0]])
    assert inside_table_boxes(pts, boxes, margin=0.0).tolist() == [True, False, False, False, False]
    assert inside_table_boxes(pts, boxes, margin=0.04).tolist() == [True, True, False, True, False]
    assert inside_table_boxes(pts, np.zeros((0, 4))).sum() == 0


def test_diamonds_off_table_counts_per_image_with_a_table_box():
    boxes = np.array([[10, 10, 14, 14], [300, 300, 304, 304], [20, 20, 40, 40], [50, 50, 54, 54.0]])
    det = Detections(boxes, np.array([0.9, 0.9, 0.9, 0.1]), np.array([4, 4, 2, 4]))
    table = np.array([[0.0, 0.0, 100.0, 100.0]])
    report = diamonds_off_table([det, det, det], [table, None, np.zeros((0, 4))], conf=0.25)
    assert report == {"images": 1, "on_table_per_image": 1.0, "off_table_per_image": 1.0}
