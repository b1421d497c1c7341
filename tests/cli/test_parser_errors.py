"""Every command answers a usage error with one line on stderr and exit code 2."""

import pytest

from pix2pockets.cli.main import build_parser, main

COMMANDS = sorted(next(a for a in build_parser()._actions if a.dest == "command").choices)


@pytest.mark.parametrize("command", COMMANDS)
def test_unknown_option_is_one_line(command, capsys):
    with pytest.raises(SystemExit) as exc:
        main([command, "--no-such-option"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith(f"pix2pockets {command}") and ": error: " in err
    assert len(err.strip().splitlines()) == 1 and "usage:" not in err


def test_bad_group_is_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["suggest", "--group", "nonsense"])
    assert exc.value.code == 2
    assert capsys.readouterr().err == (
        "pix2pockets suggest: error: argument --group: invalid choice: 'nonsense' (choose from 'auto', 'solids', "
        "'stripes', 'reds', 'yellows') (see 'pix2pockets suggest --help')\n"
    )


def test_unknown_command_is_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["nonsense"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("pix2pockets: error: argument COMMAND: invalid choice: 'nonsense'")
    assert len(err.strip().splitlines()) == 1


def test_a_command_parses_with_only_its_own_module():
    parser = build_parser("serve")
    choices = next(a for a in parser._actions if a.dest == "command").choices
    assert list(choices) == ["serve"]
    assert len(next(a for a in build_parser("train-ball-classifier")._actions if a.dest == "command").choices) > 1
