"""pix2pockets: shot suggestions for 8-ball pool from a single photo of the table."""

__version__ = "0.1.0"

from pix2pockets.env.registration import register_envs as _register_envs

_register_envs()  # gymnasium ids pix2pockets/*-v0 (cheap; the environments import lazily)


def suggest(image, group: str = "auto", **kwargs):
    """The best shot for a photo of a pool table; see :func:`pix2pockets.pipeline.photo.suggest`.

    Example:
        >>> import pix2pockets
        >>> result = pix2pockets.suggest("table.jpg", group="solids")  # doctest: +SKIP
        >>> result.to_dict()["suggestion"]["pocket"]  # doctest: +SKIP
        'top-right'
    """
    from pix2pockets.pipeline.photo import suggest as _suggest

    return _suggest(image, group=group, **kwargs)
