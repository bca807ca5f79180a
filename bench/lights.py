"""What soft shadows and area lights cost (issue 20: "frame time of each new feature against the
same scene without it"): examples rendered with FULL at their own settings, as they are (hard
lights), with every light soft (points and spots of radius 0.25, suns of 5 degrees), and with
every point light an area light (a 1 x 1 square of the same power). Each configuration's frame time
is the median of --runs renders, taken in one run so that they compare as ratios; the fragment
invocations are the library's own counts. Prints a table and writes bench/results/lights.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/lights.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import example_configurations  # noqa: E402


def hard(scene):
    pass


def soft(scene):
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "SUN":
            obj.data.angle = math.radians(5.0)
        elif obj.type == "LIGHT":
            obj.data.shadow_soft_size = 0.25


def area(scene):
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "POINT":
            obj.data.type = "AREA"
            light = obj.data  # the same datablock, now of the area light's type
            light.shape, light.size = "SQUARE", 1.0


CONFIGURATIONS = [("hard", hard), ("soft", soft), ("area", area)]


def main():
    args = example_configurations.arguments("lights.json")
    example_configurations.run("LIGHTS", "lights.py", "lights", CONFIGURATIONS, args)
    os._exit(0)


main()
