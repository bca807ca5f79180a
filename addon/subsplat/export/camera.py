"""The scene camera, or a viewport's view, as Camera data."""
from .data import Camera, ExportError, column_major


def camera_data(scene, depsgraph, width, height):
    """The scene camera for a width x height image; a panoramic camera is refused (SubSplat renders
    through a projection matrix)."""
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
    return Camera(world_to_view=column_major(camera.matrix_world.inverted_safe()),
                  view_to_clip=column_major(projection), orthographic=camera.data.type == "ORTHO")


def view_data(region_data):
    """A 3D viewport's view (context.region_data)."""
    return Camera(world_to_view=column_major(region_data.view_matrix),
                  view_to_clip=column_major(region_data.window_matrix),
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
