"""Are Blender's evaluated positions and corner normals of a deformed mesh the same in every
process? Runs N Blender processes that each read finger_pose.blend's Finger at one frame through
the add-on's export and print digests of the arrays the library would get (docs/ANIMATION.md).

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
from subsplat import export
scene = bpy.context.scene
scene.frame_set({frame})
finger = bpy.data.objects["Finger"].evaluated_get(bpy.context.evaluated_depsgraph_get())
mesh = finger.to_mesh()
positions, normals, triangles, slots = export.mesh_arrays(mesh)
print("DIGESTS", hashlib.md5(positions.tobytes()).hexdigest(), hashlib.md5(normals.tobytes()).hexdigest())
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
    positions = collections.Counter()
    normals = collections.Counter()
    for (p, n), count in seen.items():
        positions[p] += count
        normals[n] += count
    print(f"{args.runs} processes, frame {args.frame}: {len(positions)} distinct position arrays, "
          f"{len(normals)} distinct normal arrays {sorted(normals.values(), reverse=True)}")


if __name__ == "__main__":
    main()
