"""A stand-in for bpy.types.UILayout, for running a panel's draw() where no window exists (Blender
in background mode, the `bpy` module): every call is checked against the running Blender, so a
property, operator or icon that a version renamed or dropped fails the test instead of leaving a
hole in the panel that only an artist would see.

    layout = MockLayout()
    SUBSPLAT_PT_render.draw(types.SimpleNamespace(layout=layout), context)
    layout.labels, layout.props, layout.problems
"""
import bpy


def _enum_keys(function, parameter):
    return set(bpy.types.UILayout.bl_rna.functions[function].parameters[parameter].enum_items.keys())


class MockLayout:
    """Records labels, properties and operators of a draw(); problems lists what this Blender lacks."""

    ICONS = None
    ATTRIBUTES = None

    def __init__(self, root=None):
        if MockLayout.ICONS is None:
            MockLayout.ICONS = _enum_keys("label", "icon")
            MockLayout.ATTRIBUTES = set(bpy.types.UILayout.bl_rna.properties.keys())
        self.__dict__["root"] = root if root is not None else self
        if root is None:
            self.__dict__.update(labels=[], props=[], operators=[], problems=[])

    def __setattr__(self, name, value):
        if name not in self.ATTRIBUTES:
            self.root.problems.append(f"UILayout has no attribute '{name}'")

    def _icon(self, kwargs):
        icon = kwargs.get("icon", "NONE")
        if icon not in self.ICONS:
            self.root.problems.append(f"no icon '{icon}'")

    def _property(self, data, name):
        if name not in data.bl_rna.properties:
            self.root.problems.append(f"{data.bl_rna.identifier} has no property '{name}'")
        else:
            self.root.props.append(name)

    def _operator(self, idname):
        module, _, name = idname.partition(".")
        try:
            getattr(getattr(bpy.ops, module), name).get_rna_type()
        except (AttributeError, KeyError):
            self.root.problems.append(f"no operator '{idname}'")
        self.root.operators.append(idname)

    def _child(self, *_args, **_kwargs):
        return MockLayout(self.root)

    row = column = box = split = column_flow = grid_flow = _child

    def label(self, text="", **kwargs):
        self._icon(kwargs)
        self.root.labels.append(text)

    def separator(self, **_kwargs):
        pass

    def prop(self, data, property, **kwargs):  # noqa: A002 (UILayout's own name)
        self._icon(kwargs)
        self._property(data, property)

    def operator(self, idname, **kwargs):
        self._icon(kwargs)
        self._operator(idname)
        return _OperatorProperties()

    def template_ID(self, data, property, new="", open="", **_kwargs):  # noqa: A002
        self._property(data, property)
        for idname in (new, open):
            if idname:
                self._operator(idname)

    def __getattr__(self, name):
        self.root.problems.append(f"MockLayout has no '{name}' (add it, checked against UILayout)")
        return self._child


class _OperatorProperties:
    """What layout.operator() returns: the operator's properties, set by the panel."""

    def __setattr__(self, name, value):
        pass
