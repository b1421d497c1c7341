"""The web page: upload a photo, get the best shot (a thin shell over :mod:`pix2pockets.pipeline`).

Needs the ``web`` extra (fastapi, python-multipart, uvicorn). Run it with ``pix2pockets serve``.
"""
