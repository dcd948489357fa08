"""Scene files, ground motions, results, VTK and plots."""


def write_scene(scene, path):
    """Write a scene file that loads back equal; see :func:`pounding.io.scene_writer.write_scene`."""
    from pounding.io.scene_writer import write_scene as _write

    return _write(scene, path)
