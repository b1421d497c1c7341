"""pix2pockets: shot suggestions for 8-ball pool from a single photo of the table."""

__version__ = "0.1.0"

from pix2pockets.env.registration import register_envs as _register_envs

_register_envs()  # gymnasium ids pix2pockets/*-v0 (cheap; the environments import lazily)
