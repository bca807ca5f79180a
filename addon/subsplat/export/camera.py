"""The scene camera, or a viewport's view, as Camera data."""
import dataclasses

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


def border_rect(render, width, height):
    """The render border in pixels, (x, y, width, height) from the bottom left, as Blender cuts it
    (its corners truncated to whole pixels); the whole frame when the border is off."""
    if not render.use_border:
        return 0, 0, width, height
    x0, x1 = int(render.border_min_x * width), int(render.border_max_x * width)
    y0, y1 = int(render.border_min_y * height), int(render.border_max_y * height)
    x0, y0 = min(max(x0, 0), width - 1), min(max(y0, 0), height - 1)
    return x0, y0, max(min(x1, width) - x0, 1), max(min(y1, height) - y0, 1)


def bordered(camera, rect, width, height):
    """The camera (Camera data of a width x height frame) seeing only the pixels of rect (x, y, w,
    h): its clip space scaled and shifted so that the rectangle fills it."""
    x, y, w, h = rect
    if (x, y, w, h) == (0, 0, width, height):
        return camera
    # Rows of the matrix that takes the frame's clip space to the rectangle's (column-major below).
    sx, tx = width / w, (width - 2 * x - w) / w
    sy, ty = height / h, (height - 2 * y - h) / h
    p = camera.view_to_clip
    columns = [p[4 * c:4 * c + 4] for c in range(4)]
    shifted = [(sx * col[0] + tx * col[3], sy * col[1] + ty * col[3], col[2], col[3]) for col in columns]
    return dataclasses.replace(camera, view_to_clip=tuple(v for col in shifted for v in col))
