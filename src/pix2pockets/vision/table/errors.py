"""The error a table fit raises."""


class TableFitError(ValueError):
    """The table could not be found in the image; the message says why."""
