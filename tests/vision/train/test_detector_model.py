"""The exported graph: ball classes are read at the "any ball" peaks."""

import pytest

torch = pytest.importorskip("torch")

from pix2pockets.vision.detect.heads import BALL_ANY, N_OUT  # noqa: E402
from pix2pockets.vision.train.detector_model import ExportWrapper  # noqa: E402


class _Fixed(torch.nn.Module):
    def __init__(self, out: torch.Tensor) -> None:
        super().__init__()
        self.out = out

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return self.out


def test_ball_class_scores_appear_only_where_any_ball_peaks():
    raw = torch.full((1, N_OUT, 10, 10), -8.0)
    raw[0, BALL_ANY, 4, 4] = 3.0  # one ball at (4, 4)
    raw[0, 0, 4, 5] = 2.0  # cue head peaks one cell off
    raw[0, 0, 4, 4] = 1.5
    raw[0, 4, 8, 8] = 2.0  # a diamond elsewhere
    out = ExportWrapper(_Fixed(raw))(torch.zeros(1, 3, 40, 40))
    cue = out[0, 0]
    assert torch.count_nonzero(cue > 0.01) == 1
    assert float(cue[4, 4]) == pytest.approx(float(torch.sigmoid(torch.tensor(1.5))))
    assert float(out[0, 4, 8, 8]) > 0.8  # diamonds keep their own peaks
    assert float(out[0, 2].max()) < 0.01  # no solid score where no ball


def test_touching_balls_in_neighbouring_cells_both_stay_candidates():
    raw = torch.full((1, N_OUT, 10, 10), -8.0)
    raw[0, BALL_ANY, 4, 4] = 2.0  # sigmoid 0.88
    raw[0, BALL_ANY, 4, 5] = 1.0  # 0.73: within BALL_PEAK_RATIO of its neighbour, a strict peak filter drops it
    raw[0, BALL_ANY, 5, 5] = -1.0  # 0.27: a weak shoulder, not a candidate
    raw[0, 2, 4, 5] = 1.0
    out = ExportWrapper(_Fixed(raw))(torch.zeros(1, 3, 40, 40))
    assert torch.count_nonzero(out[0, BALL_ANY] > 0.01) == 2
    assert float(out[0, 2, 4, 5]) > 0.7  # its class scores are read there too
