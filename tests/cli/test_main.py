import json

import pytest

from pix2pockets.cli.main import build_parser, main


def test_help_lists_commands(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert "layout" in capsys.readouterr().out


def test_every_command_has_help(capsys):
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name in sub.choices:
        with pytest.raises(SystemExit) as exc:
            main([name, "--help"])
        assert exc.value.code == 0


def test_layout_show_bundled(capsys):
    assert main(["layout", "show"]) == 0
    assert "valid 9ft layout with 16 balls" in capsys.readouterr().out


def test_layout_check_bad_file(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"balls": [{"class": "cue", "x": 9.0, "y": 0.5}]}))
    assert main(["layout", "check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "off the playing surface" in err
    assert "Traceback" not in err
