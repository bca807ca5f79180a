"""Are the evaluated positions and corner normals of a deformed mesh the same in every process?
Runs N Blender processes that each read finger_pose.blend's Finger at one frame and print digests
of its positions, of Blender's corner normals (calc_normals_split) and of the add-on's
(export.mesh.mesh_arrays, what the library gets), then counts the distinct ones (docs/ANIMATION.md).

    python3 bench/normals_repeat.py [--runs 10] [--frame 12] [--blender blender]

with BLENDER_USER_SCRIPTS=build/scripts (the add-on staged by the build).
"""
import argparse
import collections
import os
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROBE = """
import bpy, hashlib
from subsplat.export import mesh as export_mesh
scene = bpy.context.scene
scene.frame_set({frame})
finger = bpy.data.objects["Finger"].evaluated_get(bpy.context.evaluated_depsgraph_get())
mesh = finger.to_mesh()
positions, normals, triangles, slots = export_mesh.mesh_arrays(mesh)
mesh.calc_normals_split()
blender = [0.0] * (len(mesh.loops) * 3)
mesh.loops.foreach_get("normal", blender)
digest = lambda data: hashlib.md5(data).hexdigest()
import array
print("DIGESTS", digest(positions.tobytes()), digest(array.array("f", blender).tobytes()), digest(normals.tobytes()))
"""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=10)
    parser.add_argument("--frame", type=int, default=12)
    parser.add_argument("--blender", default="blender")
    args = parser.parse_args()
    seen = collections.Counter()
    for _ in range(args.runs):
        result = subprocess.run([args.blender, "-b", "--factory-startup", "--addons", "subsplat",
                                 os.path.join(ROOT, "example_blends", "finger_pose.blend"),
                                 "--python-expr", PROBE.format(frame=args.frame)],
                                capture_output=True, text=True, check=True)
        line = next(l for l in result.stdout.splitlines() if l.startswith("DIGESTS "))
        seen[tuple(line.split()[1:])] += 1
    for k, name in enumerate(("position arrays", "Blender's normal arrays", "the add-on's normal arrays")):
        counts = collections.Counter()
        for digests, count in seen.items():
            counts[digests[k]] += count
        print(f"{args.runs} processes, frame {args.frame}: {len(counts)} distinct {name} "
              f"{sorted(counts.values(), reverse=True)}")


if __name__ == "__main__":
    main()
