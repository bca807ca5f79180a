"""Prints the SHA-256 of a deformed example frame's exported positions and normals (tests/bpy/
test_versions.py runs it in a second process: a render farm's frames must be the same numbers
whichever process makes them, docs/ANIMATION.md).

    <blender -b --factory-startup --python | build/bpy-<version>/bin/python> tests/bpy/export_hash.py
"""
import hashlib
import os
import sys

import bpy

EXAMPLE, FRAME = "finger_pose", 12  # an armature and a shape key


def export_hash():
    import subsplat
    source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    bpy.ops.wm.open_mainfile(filepath=os.path.join(source, "example_blends", f"{EXAMPLE}.blend"))
    bpy.context.scene.frame_set(FRAME)
    frame = subsplat.export.export_frame(bpy.context.evaluated_depsgraph_get(), 64, 48)
    digest = hashlib.sha256()
    for mesh in frame.meshes:
        digest.update(mesh.positions.tobytes())
        digest.update(mesh.normals.tobytes())
    return digest.hexdigest()


if __name__ == "__main__":
    import addon_utils
    addon_utils.enable("subsplat", default_set=True)
    print(f"EXPORT_HASH {export_hash()}", flush=True)
    sys.stderr.flush()
    os._exit(0)  # the 4.2.23 module crashes at exit with the add-on registered (docs/VERSIONS.md)
