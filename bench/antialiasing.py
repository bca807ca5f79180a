"""What anti-aliasing costs (issue 20: "frame time of each new feature against the same scene without
it"): examples rendered with FULL at their own settings with 1, 8 and 16 samples per pixel
(scene.subsplat.samples). The first sample is splatted; each other renders the camera's buffer, its
lights' shadow maps and the direct light again, and takes the first's exitance
(docs/ANTIALIASING.md). Each configuration's frame time is the median of --runs renders, taken in
one run so that they compare as ratios; the fragment invocations are the library's own counts.
Prints a table and writes bench/results/antialiasing.json.

    BLENDER_USER_SCRIPTS=build/scripts blender -b --factory-startup --addons subsplat \\
        --python bench/antialiasing.py [-- --examples skin_suzanne marble_pieces --percentage 30 --runs 3]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import example_configurations  # noqa: E402


def samples(count):
    def configure(scene):
        scene.subsplat.samples = count
    return configure


CONFIGURATIONS = [("1 sample", samples(1)), ("8 samples", samples(8)), ("16 samples", samples(16))]


def main():
    args = example_configurations.arguments("antialiasing.json")
    example_configurations.run("ANTIALIASING", "antialiasing.py", "samples", CONFIGURATIONS, args)
    os._exit(0)


main()
