"""The error a table fit raises."""


class TableFitError(ValueError):
    """The table could not be found in the image; the message says why."""


def counted(n: int, noun: str) -> str:
    """``n`` and the noun in the number it needs: ``1 diamond``, ``3 diamonds``."""
    return f"{n} {noun}{'s' * (n != 1)}"
