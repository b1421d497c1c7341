import json
from pathlib import Path

import numpy as np
import pytest

from pix2pockets.cli.main import main
from tests.vision.toy_table import write_toy_dataset


@pytest.fixture(scope="module")
def toy(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("toy")
    write_toy_dataset(root, 2, seed=0, split="train")
    write_toy_dataset(root, 2, seed=1, split="test")
    return root


def test_evaluate_group_lists_detector(capsys):
    with pytest.raises(SystemExit):
        main(["evaluate", "--help"])
    assert "detector" in capsys.readouterr().out


def test_evaluate_hough_writes_table_json(toy, tmp_path, capsys):
    out = tmp_path / "e.json"
    rc = main(["evaluate", "detector", "--data", str(toy), "--detector", "hough", "--json", str(out), "--quiet"])
    assert rc == 0
    rep = json.loads(out.read_text())
    assert rep["mode"] == "classes" and set(rep["before"]) >= {"cue", "dot", "average"}
    assert "AP50:95" in capsys.readouterr().out


def test_evaluate_class_aware_post_processing_is_recorded(toy, tmp_path):
    out = tmp_path / "e.json"
    args = ["evaluate", "detector", "--data", str(toy), "--detector", "hough", "--post", "class-aware"]
    assert main([*args, "--json", str(out), "--quiet"]) == 0
    rep = json.loads(out.read_text())
    assert rep["post"] == "class-aware"
    assert rep["after"]["cue"]["n_det"] <= rep["n_images"]  # at most one cue ball per image
    with pytest.raises(SystemExit):
        main([*args[:-1], "nonsense", "--json", str(tmp_path / "x.json")])
    assert not (tmp_path / "x.json").exists()


def test_evaluate_with_and_without_the_number_reader(toy, tmp_path):
    from pix2pockets.vision.detect.onnx_detector import default_model_path
    from pix2pockets.vision.stages.ball_numbers import BallNumberReader

    if not (default_model_path().exists() and BallNumberReader.default_path().exists()):
        pytest.skip("needs the committed detector and ball-number reader")
    models = {}
    for option in ([], ["--numbers", "none"]):
        out = tmp_path / f"e{len(option)}.json"
        assert main(["evaluate", "detector", "--data", str(toy), *option, "--json", str(out), "--quiet"]) == 0
        models[len(option)] = json.loads(out.read_text())["model"]
    assert "ball-numbers.onnx" in models[0] and "ball-numbers.onnx" not in models[2]


def test_evaluate_only_the_chosen_camera_kinds(toy, tmp_path, capsys):
    from pix2pockets.synth import write_dataset

    manifest = write_dataset(tmp_path / "r", 5, seed=6, size=(192, 108), split=(0, 0, 1))
    kinds = [it["camera"] for it in manifest["images"]]
    args = ["evaluate", "detector", "--detector", "hough", "--quiet"]
    out = tmp_path / "e.json"
    assert main([*args, "--data", str(tmp_path / "r"), "--cameras", kinds[0], "--json", str(out)]) == 0
    rep = json.loads(out.read_text())
    assert rep["n_images"] == kinds.count(kinds[0]) and rep["camera_kinds"] == [kinds[0]]
    absent = next(k for k in ("top", "high", "low", "jib", "phone", "phone_low") if k not in kinds)
    for data, cameras, message in (
        (tmp_path / "r", absent, f"taken with {absent} cameras"),
        (toy, "top", "no camera kind for"),  # not rendered: no sidecars
        (toy, "tv", "unknown camera kind 'tv'"),
    ):
        bad = tmp_path / "bad.json"
        assert main([*args, "--data", str(data), "--cameras", cameras, "--json", str(bad)]) == 2
        assert message in capsys.readouterr().err
        assert not bad.exists()


def test_evaluate_missing_split_is_clean_error(toy, tmp_path, capsys):
    args = ["evaluate", "detector", "--data", str(toy), "--split", "nope", "--detector", "hough"]
    rc = main([*args, "--json", str(tmp_path / "x.json")])
    assert rc == 2 and "nope" in capsys.readouterr().err
    assert not (tmp_path / "x.json").exists()


def test_detect_rejects_non_image(tmp_path, capsys):
    bad = tmp_path / "bad.jpg"
    bad.write_text("hello")
    rc = main(["detect", str(bad), "--json", str(tmp_path / "o.json")])
    assert rc == 2 and "not an image" in capsys.readouterr().err
    assert not (tmp_path / "o.json").exists()


def test_detect_needs_an_output_and_can_draw_without_json(toy, tmp_path, capsys):
    image = str(next((toy / "test" / "images").iterdir()))
    assert main(["detect", image]) == 2 and "nothing to write" in capsys.readouterr().err
    drawn = tmp_path / "d.png"
    assert main(["detect", image, "--draw", str(drawn)]) == 0
    assert drawn.read_bytes()[:4] == b"\x89PNG" and not list(tmp_path.glob("*.json"))


def test_train_detector_tiny_run_writes_onnx_and_resumes(toy, tmp_path):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    out = tmp_path / "run"
    args = ["train-detector", "--data", str(toy), "--out", str(out), "--epochs", "1", "--batch", "2"]
    args += ["--crop", "64", "--no-pretrained", "--quiet"]
    assert main(args) == 0
    assert (out / "detector.onnx").stat().st_size > 10_000 and (out / "last.pt").exists()
    assert main([*args[:6], "2", *args[7:], "--resume"]) == 0
    meta = json.loads((out / "detector.json").read_text())
    assert meta["epoch"] == 2 and meta["finished"]
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--model", str(out / "detector.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc == 0 and "after_postprocess" in json.loads((tmp_path / "d.json").read_text())


def test_train_detector_continues_from_the_shipped_onnx(toy, tmp_path):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="reading ONNX weights needs the onnx package (train extra)")
    from pix2pockets.vision.detect.onnx_detector import default_model_path

    out = tmp_path / "run"
    args = ["train-detector", "--data", str(toy), "--out", str(out), "--epochs", "1", "--batch", "2", "--crop", "64"]
    args += ["--no-pretrained", "--quiet", "--lr", "1e-9", "--init", str(default_model_path())]
    assert main(args) == 0
    assert json.loads((out / "detector.json").read_text())["config"]["init"] == str(default_model_path())
    # at a vanishing learning rate the exported model still finds what the shipped one finds
    image = str(next((toy / "test" / "images").iterdir()))
    found = []
    for model in (default_model_path(), out / "detector.onnx"):
        rc = main(
            [
                "detect",
                image,
                "--model",
                str(model),
                "--classifier",
                "none",
                "--json",
                str(tmp_path / "d.json"),
                "--force",
            ]
        )
        assert rc == 0
        found.append(len(json.loads((tmp_path / "d.json").read_text())["after_postprocess"]))
    assert found[0] > 0 and abs(found[0] - found[1]) <= max(2, found[0] // 5)


def test_train_detector_init_must_exist(toy, tmp_path, capsys):
    args = ["train-detector", "--data", str(toy), "--out", str(tmp_path / "r"), "--init", str(tmp_path / "no.onnx")]
    assert main([*args, "--no-pretrained", "--quiet"]) == 2
    assert "no.onnx" in capsys.readouterr().err
    for name in ("bad.onnx", "bad.pt"):
        (tmp_path / name).write_text("not weights")
        assert main([*args[:-1], str(tmp_path / name), "--no-pretrained", "--quiet"]) == 2
        assert name in capsys.readouterr().err


def test_export_only_int8_quantises_an_existing_onnx(toy, tmp_path, capsys):
    pytest.importorskip("onnx", reason="quantisation needs the onnx package (train extra)")
    from pix2pockets.vision.detect.onnx_detector import default_model_path

    out = tmp_path / "run"
    out.mkdir()
    args = ["train-detector", "--out", str(out), "--export-only", "--data", str(toy)]
    assert main(args) == 2  # no checkpoint and nothing to quantise
    assert "no checkpoint" in capsys.readouterr().err
    (out / "detector.onnx").write_bytes(default_model_path().read_bytes())
    assert main([*args, "--int8"]) == 0
    assert (out / "detector-int8.onnx").stat().st_size > 100_000
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--model", str(out / "detector-int8.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc == 0 and json.loads((tmp_path / "d.json").read_text())["after_postprocess"]


def test_export_only_init_rewrites_onnx_weights_with_the_current_graph(toy, tmp_path, capsys):
    pytest.importorskip("onnx", reason="reading ONNX weights needs the onnx package (train extra)")
    from pix2pockets.vision.detect.onnx_detector import default_model_path

    out = tmp_path / "run"
    args = ["train-detector", "--out", str(out), "--export-only", "--data", str(toy), "--init"]
    assert main([*args, str(tmp_path / "missing.onnx")]) == 2
    assert "missing.onnx" in capsys.readouterr().err
    assert main([*args, str(default_model_path())]) == 0
    other = tmp_path / "other.onnx"
    other.write_bytes(default_model_path().read_bytes())
    assert main([*args, str(other)]) == 2  # would overwrite a different OUT/detector.onnx
    assert "exists" in capsys.readouterr().err
    assert main([*args, str(out / "detector.onnx")]) == 0  # rewriting a file in place is asked for
    image = str(next((toy / "test" / "images").iterdir()))
    found = []
    for model in (default_model_path(), out / "detector.onnx"):
        rc = main(["detect", image, "--model", str(model), "--json", str(tmp_path / "d.json"), "--force"])
        assert rc == 0
        found.append(len(json.loads((tmp_path / "d.json").read_text())["after_postprocess"]))
    assert found[0] > 0 and abs(found[0] - found[1]) <= 2  # the same network: the same objects


def test_detect_and_evaluate_refuse_to_overwrite_without_force(toy, tmp_path, capsys):
    out = tmp_path / "e.json"
    out.write_text("keep me")
    args = ["evaluate", "detector", "--data", str(toy), "--detector", "hough", "--json", str(out), "--quiet"]
    assert main(args) == 2
    assert "--force" in capsys.readouterr().err and out.read_text() == "keep me"
    assert main([*args, "--force"]) == 0
    assert json.loads(out.read_text())["mode"] == "classes"


def test_train_ball_classifier_tiny_run_and_detect_with_it(toy, tmp_path):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    out = tmp_path / "clf"
    assert main(["train-ball-classifier", "--data", str(toy), "--out", str(out), "--epochs", "1", "--quiet"]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert len(metrics["test_confusion"]) == 5 and sum(metrics["train_counts"]) > 0
    image = str(next((toy / "test" / "images").iterdir()))
    clf = str(out / "ball-classifier.onnx")
    assert main(["detect", image, "--classifier", clf, "--json", str(tmp_path / "d.json")]) == 0
    assert json.loads((tmp_path / "d.json").read_text())["classifier"] == clf
    assert main(["detect", image, "--classifier", "none", "--json", str(tmp_path / "e.json")]) == 0
    assert json.loads((tmp_path / "e.json").read_text())["classifier"] is None


def test_train_ball_classifier_widths(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    args = ["train-ball-classifier", "--data", str(toy), "--epochs", "1", "--quiet"]
    assert main([*args, "--out", str(tmp_path / "a"), "--widths", "8,8,8"]) == 0
    assert json.loads((tmp_path / "a" / "metrics.json").read_text())["config"]["widths"] == [8, 8, 8]
    assert main([*args, "--out", str(tmp_path / "b"), "--widths", "8,8"]) == 2
    assert "three" in capsys.readouterr().err and not (tmp_path / "b").exists()


def test_train_ball_classifier_head_copies_and_jitter(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    args = ["train-ball-classifier", "--data", str(toy), "--epochs", "1", "--quiet", "--widths", "8,8,8"]
    extra = ["--head", "mean", "--copies", "2", "--centre-jitter", "0.12", "--scale-jitter", "0.85,1.18"]
    extra += ["--low-res", "0.1", "--class-power", "0.25", "--icon-negatives", "0.5"]
    assert main([*args, "--out", str(tmp_path / "a"), *extra]) == 0
    metrics = json.loads((tmp_path / "a" / "metrics.json").read_text())
    config = metrics["config"]
    assert (config["head"], config["copies"], config["centre_jitter"]) == ("mean", 2, 0.12)
    assert (config["scale_jitter"], config["low_res"], config["class_power"]) == ([0.85, 1.18], 0.1, 0.25)
    assert config["icon_negatives"] == 0.5
    plain = ["--head", "mean", "--copies", "2", "--centre-jitter", "0.12", "--scale-jitter", "0.85,1.18"]
    assert main([*args, "--out", str(tmp_path / "p"), *plain, "--low-res", "0.1", "--class-power", "0.25"]) == 0
    counts = metrics["train_counts"]  # the icons are "no ball" crops, half as many as the ball crops
    plain_counts = json.loads((tmp_path / "p" / "metrics.json").read_text())["train_counts"]
    assert counts[:4] == plain_counts[:4] and counts[4] - plain_counts[4] == round(0.5 * sum(counts[:4]))
    assert main([*args, "--out", str(tmp_path / "b"), "--scale-jitter", "1.2"]) == 2
    assert "--scale-jitter" in capsys.readouterr().err and not (tmp_path / "b").exists()
    assert main([*args, "--out", str(tmp_path / "c"), "--low-res", "1.5"]) == 2
    assert "low_res" in capsys.readouterr().err and not (tmp_path / "c").exists()


def test_train_diamond_refiner_tiny_run_and_detect_with_it(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    out = tmp_path / "ref"
    args = [
        "train-diamond-refiner",
        "--data",
        str(toy),
        "--epochs",
        "1",
        "--copies",
        "1",
        "--widths",
        "4,8,8",
        "--quiet",
    ]
    assert main([*args, "--out", str(out)]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["train_crops"] > 0 and metrics["test"]["crops"] > 0
    image = str(next((toy / "test" / "images").iterdir()))
    ref = str(out / "diamond-refiner.onnx")
    assert main(["detect", image, "--diamond-refiner", ref, "--json", str(tmp_path / "d.json")]) == 0
    assert json.loads((tmp_path / "d.json").read_text())["diamond_refiner"] == ref
    assert main(["detect", image, "--diamond-refiner", "none", "--json", str(tmp_path / "e.json")]) == 0
    assert json.loads((tmp_path / "e.json").read_text())["diamond_refiner"] is None
    assert main([*args, "--out", str(tmp_path / "bad"), "--centre-jitter", "-1"]) == 2
    assert "centre_jitter" in capsys.readouterr().err and not (tmp_path / "bad").exists()


def test_train_ball_refiner_tiny_run_and_detect_with_it(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    out = tmp_path / "ref"
    args = ["train-ball-refiner", "--data", str(toy), "--epochs", "1", "--copies", "1", "--widths", "4,8,8", "--quiet"]
    assert main([*args, "--out", str(out), "--stretch", "0.5"]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["train_crops"] > 0 and metrics["test"]["crops"] > 0 and metrics["config"]["stretch"] == 0.5
    assert set(metrics["test"]["after"]) == {"iou_median", "iou_p10", "at_iou_50", "at_iou_75"}
    image = str(next((toy / "test" / "images").iterdir()))
    ref = str(out / "ball-refiner.onnx")
    assert main(["detect", image, "--ball-refiner", ref, "--json", str(tmp_path / "d.json")]) == 0
    assert json.loads((tmp_path / "d.json").read_text())["ball_refiner"] == ref
    assert main(["detect", image, "--ball-refiner", "none", "--json", str(tmp_path / "e.json")]) == 0
    assert json.loads((tmp_path / "e.json").read_text())["ball_refiner"] is None
    assert main([*args, "--out", str(tmp_path / "bad"), "--stretch", "2"]) == 2
    assert "stretch" in capsys.readouterr().err and not (tmp_path / "bad").exists()


def test_detect_with_a_missing_ball_refiner_is_a_clean_error(toy, tmp_path, capsys):
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--ball-refiner", str(tmp_path / "no.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc != 0 and "ball refiner model not found" in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def test_detect_with_a_missing_number_reader_is_a_clean_error(toy, tmp_path, capsys):
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--numbers", str(tmp_path / "no.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc != 0 and "ball-number reader model not found" in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def test_detect_with_a_missing_diamond_refiner_is_a_clean_error(toy, tmp_path, capsys):
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--diamond-refiner", str(tmp_path / "no.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc != 0 and "diamond refiner model not found" in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def test_detect_with_a_missing_classifier_is_a_clean_error(toy, tmp_path, capsys):
    image = str(next((toy / "test" / "images").iterdir()))
    rc = main(["detect", image, "--classifier", str(tmp_path / "no.onnx"), "--json", str(tmp_path / "d.json")])
    assert rc != 0 and "ball classifier model not found" in capsys.readouterr().err
    assert not (tmp_path / "d.json").exists()


def test_table_class_needs_agnostic_mode(toy, tmp_path, capsys):
    args = ["evaluate", "detector", "--data", str(toy), "--detector", "hough", "--table-class", "1"]
    assert main([*args, "--json", str(tmp_path / "r.json"), "--quiet"]) != 0
    assert "--agnostic" in capsys.readouterr().err


def test_train_detector_stretch_options(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    args = ["train-detector", "--data", str(toy), "--out", str(tmp_path / "r"), "--no-pretrained", "--quiet"]
    assert main([*args, "--stretch", "0.5"]) == 2
    assert "--stretch needs two" in capsys.readouterr().err
    assert main([*args, "--stretch", "2,0.5", "--stretch-fraction", "0.5"]) == 2
    assert "stretch range" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()


def test_train_detector_records_the_stretch_settings(toy, tmp_path):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    out = tmp_path / "run"
    args = ["train-detector", "--data", str(toy), "--out", str(out), "--epochs", "1", "--batch", "2", "--crop", "64"]
    args += ["--no-pretrained", "--quiet", "--stretch", "0.5,0.6", "--stretch-fraction", "1"]
    assert main(args) == 0
    augment = json.loads((out / "detector.json").read_text())["config"]["augment"]
    assert augment["stretch_range"] == [0.5, 0.6] and augment["stretch_fraction"] == 1.0 and augment["crop"] == 64


def test_train_ball_numbers_tiny_run_on_renders(tmp_path, capsys):
    pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    from pix2pockets.vision.stages.ball_numbers import N_NUMBERS, BallNumberReader

    data = tmp_path / "renders"
    assert main(["synth", "--n", "2", "--out", str(data), "--size", "320x180", "--split", "0.5,0,0.5", "--seed", "3",
                 "--no-progress"]) == 0  # fmt: skip
    out = tmp_path / "num"
    args = ["train-ball-numbers", "--data", str(data), "--out", str(out), "--epochs", "1", "--widths", "4,8,8"]
    assert main([*args, "--quiet"]) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert len(metrics["train_counts"]) == N_NUMBERS and sum(metrics["train_counts"]) > 0
    assert 0 <= metrics["test"]["accuracy_within_class"] <= 1
    reader = BallNumberReader(out / "ball-numbers.onnx")
    assert reader.read(np.zeros((60, 60, 3), np.uint8), np.array([[20.0, 20, 40, 40]])).shape == (1, N_NUMBERS)
    image = str(next((data / "test" / "images").iterdir()))
    onnx = str(out / "ball-numbers.onnx")
    assert main(["detect", image, "--numbers", onnx, "--conf", "0.05", "--json", str(tmp_path / "d.json")]) == 0
    report = json.loads((tmp_path / "d.json").read_text())
    assert report["number_reader"] == onnx
    balls = [d for d in report["after_postprocess"] if d["class"] != "dot"]
    assert balls and all("number" in d for d in balls)
    assert main(["detect", image, "--numbers", "none", "--json", str(tmp_path / "e.json")]) == 0
    report = json.loads((tmp_path / "e.json").read_text())
    assert report["number_reader"] is None and not any("number" in d for d in report["after_postprocess"])


def test_train_ball_numbers_refuses_data_without_sidecars(toy, tmp_path, capsys):
    pytest.importorskip("torch")
    args = ["train-ball-numbers", "--data", str(toy), "--out", str(tmp_path / "n"), "--epochs", "1", "--quiet"]
    assert main(args) == 2
    assert "sidecar" in capsys.readouterr().err


def test_train_table_tiny_run_writes_a_model_the_pipeline_reads(tmp_path, capsys):
    pytest.importorskip("torch")
    from pix2pockets.synth import write_dataset
    from pix2pockets.vision.table.keypoints import TableModel

    data = tmp_path / "renders"
    write_dataset(data, 6, seed=3, size=(192, 108), split=(0.5, 0.5, 0))
    out = tmp_path / "table"
    args = ["train-table", "--data", str(data), "--out", str(out), "--epochs", "1", "--batch", "2", "--device", "cpu"]
    assert main(args) == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["history"][0]["epoch"] == 1 and 0.0 <= metrics["history"][0]["surface_iou"] <= 1.0
    cues = TableModel(out / "table.onnx").read(np.zeros((108, 192, 3), dtype=np.uint8))
    assert cues.surface.ndim == 2 and cues.surface.shape[1] == 192 // 4 * 2
    assert main(["train-table", "--out", str(tmp_path / "x")]) == 2  # no data: a clean error
    assert "give at least one --data" in capsys.readouterr().err


def test_train_detector_batches_do_not_depend_on_the_loading_processes(toy, tmp_path):
    torch = pytest.importorskip("torch")
    pytest.importorskip("onnx", reason="ONNX export needs the onnx package (train extra)")
    weights = []
    for workers in (0, 2):
        out = tmp_path / f"w{workers}"
        args = ["train-detector", "--data", str(toy), "--out", str(out), "--epochs", "1", "--batch", "2"]
        args += ["--crop", "64", "--no-pretrained", "--quiet", "--workers", str(workers)]
        assert main(args) == 0
        weights.append(torch.load(out / "last.pt", map_location="cpu", weights_only=False)["model"])
    assert weights[0].keys() == weights[1].keys()
    assert all(torch.equal(weights[0][k], weights[1][k]) for k in weights[0])


def test_train_detector_refuses_a_missing_gpu_and_bad_workers(toy, tmp_path, capsys):
    torch = pytest.importorskip("torch")
    base = ["train-detector", "--data", str(toy), "--out", str(tmp_path / "r"), "--quiet"]
    assert main([*base, "--workers", "-1"]) == 2
    assert "workers" in capsys.readouterr().err
    if not torch.cuda.is_available():
        assert main([*base, "--device", "cuda", "--no-pretrained"]) == 2
        assert "CUDA" in capsys.readouterr().err
