"""Sphinx extension: the scene-file reference, generated from the schema at build time."""


def setup(app):
    return {"version": "1", "parallel_read_safe": True}
