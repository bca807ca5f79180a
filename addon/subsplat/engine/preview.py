"""Material previews (the Material Properties' preview and the slot icons): Blender's preview
scene rendered like a final frame, without its warnings (its area lights are Blender's, not the
user's) and without saving a scene file."""
from . import final


def render(engine, depsgraph):
    final.render_image(engine, depsgraph, preview=True)
