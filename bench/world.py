"""What the world light costs (issue 20: "frame time of each new feature against the same scene
without it"): examples rendered with FULL at their own settings, with a black world (no world
light), and with a uniform world drawn unshadowed, in 8 and in 16 shadowed directions
(scene.subsplat.world_directions; docs/WORLD.md). Each configuration's frame time is the median of
--runs renders, taken in one run so that they compare as ratios; the fragment invocations and light
views are the library's own counts. Prints a table and writes bench/results/world.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/world.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import example_configurations  # noqa: E402


def world(directions):
    """A black world (None), or the example's own world drawn with `directions`."""
    def configure(scene):
        scene.world.use_nodes = False
        if directions is None:
            scene.world.color = (0.0, 0.0, 0.0)
        else:
            scene.subsplat.world_directions = directions
    return configure


CONFIGURATIONS = [("no world", world(None)), ("unshadowed", world(-1)), ("8 directions", world(8)),
                  ("16 directions", world(16))]


def main():
    args = example_configurations.arguments("world.json")
    example_configurations.run("WORLD", "world.py", "world", CONFIGURATIONS, args)
    os._exit(0)


main()
