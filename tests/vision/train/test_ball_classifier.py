"""The crop classifier network: both heads give five classes; the grid head can tell where colour sits; a
blackball render's yellows are taught as plain balls."""

import json
from pathlib import Path

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.metrics.yolo_data import LabelledImage  # noqa: E402
from pix2pockets.vision.stages.ball_classifier import BallClassifier  # noqa: E402
from pix2pockets.vision.stages.crops import CROP_SIZE, crop_balls  # noqa: E402
from pix2pockets.vision.train.ball_classifier import (  # noqa: E402
    CropNet,
    CropTrainConfig,
    export_crop_classifier,
    plain_object_balls,
)


@pytest.mark.parametrize("head", ["grid", "mean"])
def test_both_heads_give_five_logits_per_crop(head):
    net = CropNet((4, 8, 8), head).eval()
    assert net(torch.zeros(3, 3, CROP_SIZE, CROP_SIZE)).shape == (3, 5)


def test_unknown_head_bad_copies_and_bad_jitter_are_refused():
    with pytest.raises(ValueError, match="head"):
        CropNet(head="max")
    with pytest.raises(ValueError, match="head"):
        CropTrainConfig(data=("d",), out="o", head="max")
    with pytest.raises(ValueError, match="copies"):
        CropTrainConfig(data=("d",), out="o", copies=0)
    with pytest.raises(ValueError, match="jitter"):
        CropTrainConfig(data=("d",), out="o", scale_jitter=(1.1, 0.9))
    with pytest.raises(ValueError, match="jitter"):
        CropTrainConfig(data=("d",), out="o", centre_jitter=-0.1)
    with pytest.raises(ValueError, match="crop_size"):
        CropTrainConfig(data=("d",), out="o", crop_size=44)
    with pytest.raises(ValueError, match="icon_negatives"):
        CropTrainConfig(data=("d",), out="o", icon_negatives=1.5)
    with pytest.raises(ValueError, match="hard_negatives"):
        CropTrainConfig(data=("d",), out="o", hard_negatives=-1)
    with pytest.raises(ValueError, match="no classifier file"):
        CropTrainConfig(data=("d",), out="o", init="missing.onnx")


def _disc_and_cap() -> tuple[torch.Tensor, torch.Tensor]:
    """A white disc filling the ball's outline (label 0, cue) and a smaller white cap (label 3, a stripe seen
    from its pole with the band the colour of the cloth), at the same mean brightness."""
    yy, xx = np.mgrid[0:CROP_SIZE, 0:CROP_SIZE] + 0.5
    r = np.hypot(xx - CROP_SIZE / 2, yy - CROP_SIZE / 2)
    disc = np.where(r < CROP_SIZE / 3, 200.0, 80.0)
    cap = np.where(r < CROP_SIZE / 5, 200.0, 80.0)
    cap *= disc.mean() / cap.mean()
    x = torch.tensor(np.stack([disc, cap]), dtype=torch.float32)[:, None].repeat(1, 3, 1, 1)
    return x, torch.tensor([0, 3])


def test_grid_head_learns_to_tell_a_full_disc_from_a_cap():
    torch.manual_seed(0)
    x, y = _disc_and_cap()
    net = CropNet((4, 8, 8), "grid")
    opt = torch.optim.Adam(net.parameters(), lr=1e-2)
    for _ in range(40):
        loss = torch.nn.functional.cross_entropy(net(x), y)
        opt.zero_grad()
        loss.backward()
        opt.step()
    net.eval()
    assert torch.equal(net(x).argmax(1), y)


def test_exported_classifier_runs_in_onnxruntime(tmp_path):
    net = CropNet((4, 8, 8), "grid").eval()
    path = export_crop_classifier(net, tmp_path / "clf.onnx", CROP_SIZE)
    clf = BallClassifier(path)
    image = np.full((120, 160, 3), 90, np.uint8)
    probs = clf.classify(image, np.array([[10, 10, 30, 30], [50, 40, 80, 70.0]]))
    assert probs.shape == (2, 5) and np.allclose(probs.sum(1), 1, atol=1e-5)
    with torch.no_grad():
        crops = torch.from_numpy(np.full((1, CROP_SIZE, CROP_SIZE, 3), 90, np.uint8)).permute(0, 3, 1, 2).float()
        expected = torch.softmax(net(crops), 1).numpy()
    assert np.allclose(probs[0], expected[0], atol=1e-4)


def test_a_classifier_of_another_crop_size_is_fed_crops_of_its_size(tmp_path):
    size = 48
    net = CropNet((4, 8, 8), "grid", crop_size=size).eval()
    clf = BallClassifier(export_crop_classifier(net, tmp_path / "clf48.onnx", size))
    assert clf.crop_size == size
    image = np.random.default_rng(0).integers(0, 255, (120, 160, 3), dtype=np.uint8)
    box = np.array([[50, 40, 80, 70.0]])
    with torch.no_grad():
        crops = crop_balls(image, np.array([[65.0, 55.0]]), np.array([30.0]), size)
        expected = torch.softmax(net(torch.from_numpy(crops).permute(0, 3, 1, 2).float()), 1).numpy()
    assert np.allclose(clf.classify(image, box, aspect=1.0), expected, atol=1e-4)


@pytest.mark.parametrize(("ball_set", "taught"), [("blackball", [0, 1, 2, 2, 4]), ("american", [0, 1, 2, 3, 4])])
def test_a_blackball_renders_yellows_are_taught_as_plain_balls(tmp_path, ball_set, taught):
    (tmp_path / "meta").mkdir()
    (tmp_path / "meta" / "a.json").write_text(json.dumps({"ball_set": ball_set}))
    ids = np.array([0, 1, 2, 3, 4])  # cue, black, red (solid id), yellow (stripe id), a diamond
    item = LabelledImage(Path(tmp_path / "images" / "a.jpg"), np.zeros((5, 4)), ids, np.full((5, 2), np.nan), (64, 64))
    identity = {i: i for i in range(5)}
    assert plain_object_balls(item, identity).class_id.tolist() == taught
    # a dataset that numbers the classes otherwise: its own stripe id becomes its own solid id
    shuffled = {0: 3, 1: 2, 2: 1, 3: 0, 4: 4}  # dataset id -> ours (dataset 0 is our stripe, 1 our solid)
    expect = [1, 1, 2, 3, 4] if ball_set == "blackball" else ids.tolist()
    assert plain_object_balls(item, shuffled).class_id.tolist() == expect


def test_the_bundled_classifier_loads_back_into_its_network():
    from pix2pockets.vision.train.ball_classifier import load_crop_net

    rng = np.random.default_rng(0)
    crops = rng.integers(0, 256, (16, CROP_SIZE, CROP_SIZE, 3), dtype=np.uint8)
    shipped = BallClassifier.from_default()
    net = load_crop_net(BallClassifier.default_path(), CropNet(), crops).eval()
    with torch.no_grad():
        ours = torch.softmax(net(torch.from_numpy(crops).permute(0, 3, 1, 2).float()), dim=1).numpy()
    np.testing.assert_allclose(ours, shipped.run(crops), atol=1e-4)
    with pytest.raises(ValueError, match="shape"):
        load_crop_net(BallClassifier.default_path(), CropNet(widths=(8, 16, 32)), crops)
