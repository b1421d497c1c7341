"""pix2pockets: shot suggestions for 8-ball pool from a single photo of the table."""

__version__ = "0.1.0"
