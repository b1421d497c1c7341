import numpy as np
import pytest

from pix2pockets.vision.classes import DIAMOND_ID
from pix2pockets.vision.detect.decode import _diamond_boxes, decode_ball_peaks, decode_peaks
from pix2pockets.vision.detect.heads import BALL_ANY, CONTACT_SLICE, N_OUT, OFFSET_SLICE, SIZE_SLICE, STRIDE
from pix2pockets.vision.detect.letterbox import Letterbox, letterbox


def test_letterbox_scales_long_side_and_pads():
    img = np.zeros((300, 400, 3), np.uint8)
    out, box = letterbox(img, 640, 32)
    assert out.shape == (480, 640, 3)
    assert box.scale == pytest.approx(1.6)
    assert np.allclose(box.to_image([[640, 480]]), [[400, 300]])
    out2, _ = letterbox(np.zeros((100, 50, 3), np.uint8), 320, 32)
    assert out2.shape == (320, 160, 3)


@pytest.mark.parametrize("shape", [(10, 10), (10, 10, 4), (0, 5, 3)])
def test_letterbox_rejects_bad_images(shape):
    with pytest.raises(ValueError, match="image"):
        letterbox(np.zeros(shape, np.uint8))


def _output(h=20, w=30):
    return np.zeros((N_OUT, h, w), np.float32)


def test_decode_one_peak_maps_back_to_image_pixels():
    out = _output()
    out[2, 5, 7] = 0.9  # a solid at cell (x 7, y 5)
    out[OFFSET_SLICE, 5, 7] = [0.25, 0.5]
    out[SIZE_SLICE, 5, 7] = np.log([3.0, 2.0])  # 12 x 8 px in the network input
    out[CONTACT_SLICE, 5, 7] = [0.25, 1.5]
    det = decode_peaks(out, Letterbox(scale=2.0, size=(120, 80)), conf_threshold=0.1)
    assert len(det) == 1 and det.class_id[0] == 2 and det.confidence[0] == pytest.approx(0.9)
    cx, cy = (7.25 * STRIDE) / 2, (5.5 * STRIDE) / 2
    assert np.allclose(det.boxes[0], [cx - 3, cy - 2, cx + 3, cy + 2], atol=1e-4)
    assert np.allclose(det.contact[0], [7.25 * STRIDE / 2, 6.5 * STRIDE / 2], atol=1e-4)


def test_decode_threshold_topk_and_diamond_contact_nan():
    out = _output()
    out[4, 1, 1] = 0.8  # diamond
    out[0, 2, 2] = 0.3
    out[1, 3, 3] = 0.02
    det = decode_peaks(out, Letterbox(1.0, (120, 80)), conf_threshold=0.05, max_detections=1)
    assert det.class_id.tolist() == [4] and np.all(np.isnan(det.contact))
    assert len(decode_peaks(out, Letterbox(1.0, (120, 80)), conf_threshold=0.05)) == 2


def test_diamond_boxes_keep_the_label_floor_at_any_input_scale():
    out = _output()
    out[4, 6, 8] = 0.8  # a diamond predicted 2 x 6 px in the network input
    out[OFFSET_SLICE, 6, 8] = [0.5, 0.5]
    out[SIZE_SLICE, 6, 8] = np.log([2.0 / STRIDE, 6.0 / STRIDE])
    out[2, 2, 2] = 0.9  # a 2 px solid keeps its size
    out[SIZE_SLICE, 2, 2] = np.log(2.0 / STRIDE)
    # image at the network's size, a 720p frame (0.8), and a 1080p frame (0.53) or larger (0.5)
    for scale, width, height in ((1.0, 4.0, 6.0), (0.8, 4.0, 6.5), (0.5, 4.0 + 0.375 * 3.0, 11.0)):
        det = decode_peaks(out, Letterbox(scale, (120, 80)))
        diamond, ball = det.boxes[det.class_id == DIAMOND_ID][0], det.boxes[det.class_id == 2][0]
        cx, cy = 8.5 * STRIDE / scale, 6.5 * STRIDE / scale
        # the floor stays up to 720p; the 6 px side, 6 / scale px in the image, is read at most 1 px short
        assert np.allclose(diamond, [cx - width / 2, cy - height / 2, cx + width / 2, cy + height / 2])
        assert ball[2] - ball[0] == pytest.approx(2.0 / scale)


def test_diamond_sizes_blend_from_the_floor_share_to_the_held_shortfall():
    centre = np.zeros((3, 2))
    net = np.array([[4.0, 4.0], [4.5, 4.5], [5.0, 5.0]])  # the floor, half-way, full hold
    sizes = _diamond_boxes(centre, net, 0.5)[:, 2] * 2
    # a floor-sized 2-8 px sight is read 5.1 px, a 10 px sight 9 px, 1 px short
    assert np.allclose(sizes, [4.0 + 0.375 * 3.0, 4.0 + 1.0 + (0.5 + 0.5 * 0.375) * 3.0, 4.0 + 2.0 + 3.0])
    assert np.allclose(_diamond_boxes(centre, net, 0.8)[:, 2] * 2, 4.0 + (net[:, 0] - 4.0) / 0.8)  # 720p unchanged


def test_decode_agnostic_reads_ball_channel():
    out = _output()
    out[BALL_ANY, 4, 4] = 0.7
    out[2, 9, 9] = 0.9
    det = decode_peaks(out, Letterbox(1.0, (120, 80)), agnostic=True)
    assert len(det) == 1 and det.confidence[0] == pytest.approx(0.7)


def _ball_cell(out, y, x, score, offset, size_px=8.0):
    out[BALL_ANY, y, x] = score
    out[2, y, x] = score  # a solid
    out[OFFSET_SLICE, y, x] = offset
    out[SIZE_SLICE, y, x] = np.log(size_px / STRIDE)


def test_candidates_of_one_ball_merge_and_touching_balls_stay_apart():
    box = Letterbox(1.0, (120, 80))
    one = _output()
    _ball_cell(one, 5, 5, 0.9, [0.5, 0.5])
    _ball_cell(one, 5, 6, 0.7, [-0.4, 0.5])  # the same ball seen from the next cell: its box lands on the first
    balls, heat = decode_ball_peaks(one, box)
    assert len(balls) == 1 and balls.confidence[0] == pytest.approx(0.9) and heat.shape == (1, 4)
    assert len(decode_peaks(one, box)) == 1 and len(decode_peaks(one, box, agnostic=True)) == 1
    two = _output()
    _ball_cell(two, 5, 5, 0.9, [0.0, 0.5])
    _ball_cell(two, 5, 6, 0.7, [1.0, 0.5])  # a touching ball 8 px away, one cell over
    assert len(decode_ball_peaks(two, box)[0]) == 2
    assert len(decode_peaks(two, box)) == 2


def test_decode_rejects_wrong_shape():
    with pytest.raises(ValueError, match="model output"):
        decode_peaks(np.zeros((5, 4, 4)), Letterbox(1.0, (16, 16)))


def _merged_by_brute_force(out, conf_threshold):
    """Each candidate cell against each of its 8 neighbours, one pair at a time."""
    from pix2pockets.vision.detect.heads import BALL_NMS_IOU
    from pix2pockets.vision.detect.postprocess import paired_box_iou

    def box(y, x):
        size = np.exp(np.clip(out[SIZE_SLICE, y, x], -4.0, 6.0))
        centre = np.array([x, y]) + out[OFFSET_SLICE, y, x]
        return np.concatenate([centre - size / 2, centre + size / 2])

    heat = np.where(out[BALL_ANY] >= conf_threshold, out[BALL_ANY], 0.0)
    h, w = heat.shape
    merged = np.zeros((h, w), bool)
    for y, x in zip(*np.nonzero(heat > 0), strict=True):
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                ny, nx = y + dy, x + dx
                if (dy or dx) and 0 <= ny < h and 0 <= nx < w and heat[ny, nx] > heat[y, x]:
                    merged[y, x] |= paired_box_iou(box(y, x), box(ny, nx)) >= BALL_NMS_IOU
    return merged


def test_merged_cells_match_a_cell_by_cell_reading():
    from pix2pockets.vision.detect.decode import merged_ball_cells

    rng = np.random.default_rng(7)
    out = np.zeros((N_OUT, 24, 30), np.float32)
    out[BALL_ANY] = np.where(rng.random((24, 30)) < 0.3, rng.random((24, 30)), 0.0)  # clusters of candidates
    out[OFFSET_SLICE] = rng.uniform(-0.6, 0.6, (2, 24, 30))
    out[SIZE_SLICE] = np.log(rng.uniform(0.8, 3.0, (2, 24, 30)))
    merged = merged_ball_cells(out, 0.05)
    np.testing.assert_array_equal(merged, _merged_by_brute_force(out, 0.05))
    assert 0 < merged.sum() < (out[BALL_ANY] >= 0.05).sum()
    assert not merged_ball_cells(np.zeros((N_OUT, 4, 4), np.float32)).any()
