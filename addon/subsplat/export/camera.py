"""The scene camera, or a viewport's view, as Camera data."""
from .data import Camera, ExportError, column_major


def camera_data(scene, depsgraph, width, height):
    """The scene camera for a width x height image."""
    camera = scene.camera
    if camera is None:
        raise ExportError("the scene has no camera")
    camera = camera.evaluated_get(depsgraph)
    render = scene.render
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height,
                                           scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    return Camera(world_to_view=column_major(camera.matrix_world.inverted_safe()),
                  view_to_clip=column_major(projection), orthographic=camera.data.type == "ORTHO")


def view_data(region_data):
    """A 3D viewport's view (context.region_data)."""
    return Camera(world_to_view=column_major(region_data.view_matrix),
                  view_to_clip=column_major(region_data.window_matrix),
                  orthographic=not region_data.is_perspective)
