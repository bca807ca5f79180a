"""The scene camera, or a viewport's view, as Camera data."""
from .data import Camera, ExportError, column_major


def camera_origin(scene, depsgraph):
    """The scene camera's position: the origin a final render's world is sent relative to
    (export.Frame.origin), so that a scene far from Blender's origin keeps its precision in the
    library's single-precision floats. (0, 0, 0) without a camera."""
    camera = scene.camera
    if camera is None:
        return (0.0, 0.0, 0.0)
    return tuple(float(v) for v in camera.evaluated_get(depsgraph).matrix_world.translation)


def camera_data(scene, depsgraph, width, height, origin=(0.0, 0.0, 0.0)):
    """The scene camera for a width x height image, in the world relative to `origin`; a panoramic
    camera is refused (SubSplat renders through a projection matrix)."""
    camera = scene.camera
    if camera is None:
        raise ExportError("the scene has no camera")
    if camera.type != "CAMERA":
        raise ExportError(f"the scene's camera '{camera.name}' is a {camera.type.lower()} object, not a camera")
    if camera.data.type == "PANO":
        raise ExportError(f"camera '{camera.name}' is panoramic: SubSplat renders perspective and orthographic "
                          "cameras only (Camera Properties > Type)")
    camera = camera.evaluated_get(depsgraph)
    render = scene.render
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height,
                                           scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    placed = camera.matrix_world.copy()
    placed.translation = [t - o for t, o in zip(camera.matrix_world.translation, origin)]
    return Camera(world_to_view=column_major(placed.inverted_safe()),
                  view_to_clip=column_major(projection), orthographic=camera.data.type == "ORTHO")


def view_data(region_data, origin=(0.0, 0.0, 0.0)):
    """A 3D viewport's view (context.region_data), in the world relative to `origin`."""
    view = region_data.view_matrix
    world_to_view = list(column_major(view))
    for row in range(3):  # view x (p + origin) = view x p + the view's rotation x origin
        world_to_view[12 + row] += sum(view[row][col] * origin[col] for col in range(3))
    return Camera(world_to_view=tuple(world_to_view), view_to_clip=column_major(region_data.window_matrix),
                  orthographic=not region_data.is_perspective)


def feature_warnings(scene):
    """What the scene's render settings and camera ask for that SubSplat does not render, one line each."""
    warnings = []
    if scene.render.use_motion_blur:
        warnings.append("motion blur is on (Render Properties > Motion Blur): SubSplat renders each frame at "
                        "its own time, without blur")
    camera = scene.camera
    if camera is not None and camera.type == "CAMERA" and camera.data.dof.use_dof:
        warnings.append(f"camera '{camera.name}' has depth of field on: SubSplat renders everything in focus")
    return warnings
