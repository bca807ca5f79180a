"""Settings on Scene (scene.subsplat) and Material (material.subsplat)."""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty, PointerProperty,
                       StringProperty)

from . import presets

METHOD_ITEMS = [
    ("BRUTE", "Brute Force", "Splat every texel of the finest irradiance buffer (Shah et al. 2009): the baseline"),
    ("MULTIRES", "Multiresolution",
     "Splat every finest irradiance texel, near distances into the full-resolution buffer and far "
     "ones into coarser buffers, gathered by bilateral upsampling (Chen et al. 2012, eq. 12-17)"),
    ("ADAPTIVE", "Adaptive",
     "Select irradiance samples from a mipmapped irradiance buffer by depth range, material range and "
     "light angle (Chen et al. 2012, eq. 10-11); splat at one level"),
    ("FULL", "Full", "Adaptive sample selection and multiresolution splatting: the paper's method"),
    ("REFERENCE", "Reference",
     "The model's reference: the same model (the classical dipole) summed in object space on the CPU with "
     "ray-traced shadows (slow); exact for the model, not for the physics, whose truth is the Cycles twin"),
    ("MATERIAL_EDIT", "Material Edit",
     "Full's samples splatted once into the transport of a basis of profiles (Xu et al. 2007); while the "
     "meshes, lights, camera and size stay as they were, an edit of a homogeneous material only recombines "
     "it (docs/MATERIAL_EDIT.md). A scene with a SubEdit material is rendered as Full"),
    ("PRECOMPUTED", "Precomputed",
     "Lensch et al. 2002: each translucent object's response precomputed once (an atlas of per-texel "
     "kernels and vertex-to-vertex factors), then relit on the CPU under moving lights and cameras. Any "
     "change of a translucent mesh (deformation, modifiers, another frame) or of a material precomputes it "
     "again (docs/PRECOMPUTED.md)"),
]


def _quality_edited(settings, _context):
    # Setting a quality parameter by hand (in the panel or from Python) makes the quality manual.
    if settings.quality != "MANUAL":
        settings.quality = "MANUAL"


QUALITY_ITEMS = [
    ("AUTO", "Automatic",
     "Irradiance resolution chosen each frame from the scene: the cheapest that is expected to meet the target "
     "error for the shortest scattering range in view; levels chosen from the ranges, thresholds at the "
     "paper's values (docs/AUTO.md)"),
    ("MANUAL", "Manual", "Irradiance resolution, levels and thresholds as set below"),
]


class SubsplatSceneSettings(bpy.types.PropertyGroup):
    method: EnumProperty(name="Method", items=METHOD_ITEMS, default="FULL",
                         description="How irradiance samples are selected and splatted")
    quality: EnumProperty(name="Quality", items=QUALITY_ITEMS, default="AUTO",
                          description="How the irradiance resolution, levels and thresholds are chosen")
    target_error: FloatProperty(
        name="Target Error", default=0.01, min=0.001, max=0.5, soft_max=0.1, precision=3, step=0.1,
        subtype="FACTOR",
        description="Automatic quality: the relative RMSE against Reference to aim for (0.01: 1 %); smaller "
                    "chooses finer irradiance buffers (slower)")
    irradiance_resolution: IntProperty(
        name="Irradiance Resolution", default=512, min=16, max=8192, soft_min=64, soft_max=2048,
        update=_quality_edited,
        description="Manual quality: texels per side of each irradiance buffer (one per sun or spot light, six "
                    "per point light). Setting it makes the quality manual")
    levels: IntProperty(
        name="Levels", default=0, min=0, max=8, update=_quality_edited,
        description="Levels of the irradiance (adaptive) and splatting (multiresolution) hierarchies; "
                    "0 chooses them each frame from the materials' scattering ranges, the lights and the "
                    "image size (the render stats say what was chosen; the paper uses 3)")
    z0_factor: FloatProperty(
        name="Depth Threshold", default=0.03, min=1e-4, max=100.0, soft_max=1.0, precision=3, update=_quality_edited,
        description="Adaptive: z0, the largest depth range under a coarse sample, as a factor of the "
                    "translucent objects' bounding-sphere radius")
    alpha: FloatProperty(
        name="Sampling Scale", default=15.0, min=0.01, max=1e4, soft_min=1.0, soft_max=100.0, update=_quality_edited,
        description="Adaptive: alpha of eq. 11; irradiance texels per effective scattering range "
                    "(larger: finer sampling, slower)")
    epsilon: FloatProperty(
        name="Error Tolerance", default=0.001, min=1e-6, max=0.5, precision=4, step=0.01, update=_quality_edited,
        description="Multiresolution: epsilon of eq. 14; the largest energy error a coarser splatting "
                    "level may make (smaller: more work at full resolution)")
    lambda_z: FloatProperty(
        name="Depth Sharpness", default=8.0, min=0.0, max=1e4, soft_max=100.0,
        description="Multiresolution: lambda_z of eq. 17; how strongly upsampling avoids depth discontinuities")
    lambda_m: FloatProperty(
        name="Material Sharpness", default=8.0, min=0.0, max=1e4, soft_max=100.0,
        description="Multiresolution: lambda_m of eq. 17 (per millimetre of R_P difference); how strongly upsampling avoids material boundaries")
    samples: IntProperty(
        name="Samples", default=8, min=1, max=1024, soft_max=64,
        description="Anti-aliasing: jittered samples per pixel in final renders, spread by the pixel filter "
                    "(Film > Pixel Filter's width). The first is splatted; each other costs a pass over the "
                    "scene and its lights' shadow maps, not a splatting (docs/ANTIALIASING.md)")
    viewport_samples: IntProperty(
        name="Viewport Samples", default=8, min=1, max=1024, soft_max=64,
        description="Anti-aliasing in the viewport: each redraw adds one jittered sample, up to this many; any "
                    "change starts again from the first")
    viewport_material_edit: BoolProperty(
        name="Fast Material Edits", default=True,
        description="Viewport with the Full method: after a change of materials alone (a slider in the Material "
                    "panel), the first sample is recombined from a precomputed transport (Material Edit, "
                    "docs/MATERIAL_EDIT.md): the first such change precomputes it (a few Full frames), the next "
                    "ones cost a fraction of a frame; any other change goes back to Full")
    viewport_budget: FloatProperty(
        name="Viewport Budget", default=200.0, min=0.0, max=1e6, soft_max=2000.0, unit="NONE",
        description="Splatting work per viewport redraw, in millions of fragments: a redraw that reaches it "
                    "shows what it has and the next goes on, until the image is complete (then the samples "
                    "go on). 200 is about 50 ms on a small GPU (docs/VIEWPORT.md); 0 renders each sample "
                    "whole, however long it takes")
    shadow_resolution: IntProperty(
        name="Shadow Resolution", default=0, min=0, max=8192, soft_max=4096,
        description="Texels per side of each light view's shadow map (hard shadows); 0 chooses them so that a "
                    "texel is no larger than a pixel of the image, up to 2048 (the render stats say what was "
                    "chosen). Soft shadows and the light through thin parts use the irradiance buffer's")
    precomputed_atlas: EnumProperty(
        name="Atlas", default="UV_MAP",
        items=[("UV_MAP", "UV Map Where It Fits",
                "Each island of a mesh's UV map is a chart of Precomputed's atlas when it is stretched no more "
                "than 1.5 times either way, has one winding and does not overlap itself; the rest is charted "
                "as if there were no UV map (the render report counts both, docs/PRECOMPUTED.md)"),
               ("MADE", "Made", "Every mesh charted by its normals, as if it had no UV map")],
        description="Precomputed: the texture atlas its kernels and factors are laid out on")
    forward_shift: BoolProperty(
        name="Forward Shift", default=True,
        description="Tabulated materials: the light entering at a slant is reflected ahead of where it enters, "
                    "along its path in the medium, as a half-space reflects it (the glow past a terminator or a "
                    "shadow's edge). Off: centred on where it enters, as Material Edit always does "
                    "(docs/TRANSPORT.md)")
    world_directions: IntProperty(
        name="World Directions", default=0, min=-1, max=64,
        description="The world's light: the directions it casts shadows from (each costs about what a sun "
                    "costs). 0 chooses from the world's share of the scene's light: unshadowed below 10 %, "
                    "8 below 50 %, else 16; -1 lights every surface unshadowed (no occlusion, no cost)")
    viewport_scale: EnumProperty(
        name="Viewport Resolution", default="1",
        items=[("1", "Full", "The viewport renders one pixel per screen pixel"),
               ("2", "1/2", "The viewport renders half the pixels across and down, and scales up"),
               ("4", "1/4", "The viewport renders a quarter of the pixels across and down, and scales up")],
        description="Rendered shading in the 3D viewport at a fraction of the region's resolution, for speed; "
                    "final renders always use the full resolution")
    debug_passes: BoolProperty(
        name="Debug Passes", default=False,
        description="Add the passes 'SubSplat Samples' (selected irradiance samples, a colour per level: "
                    "red, green, blue, yellow, ...) and 'SubSplat Level k' (each splatting level's own "
                    "exitance) to final renders (not with Reference or Material Edit, which say so)")
    scene_file: StringProperty(
        name="Save Scene File", default="", subtype="FILE_PATH",
        description="After each render, save what the library was given (meshes, materials, lights, camera, "
                    "settings) to this file: for replaying the frame without Blender (subsplat_replay) and for "
                    "bug reports. '#' characters become the frame number. Empty: off")
    reference_samples: IntProperty(
        name="Reference Samples", default=200000, min=1000, max=100000000, soft_min=10000, soft_max=4000000,
        description="Reference: surface samples spread by area over all translucent surfaces together "
                    "(at least one per triangle). Render time grows with it; see docs/ACCURACY.md")


def _apply_preset(settings, _context):
    if settings.preset == "CUSTOM":
        return
    _label, sigma_s_prime, sigma_a = presets.MEASURED_MEDIA[settings.preset]
    settings["_applying_preset"] = True
    settings.sigma_s_prime = sigma_s_prime
    settings.sigma_a = sigma_a
    settings.eta = presets.MEASURED_ETA
    settings["_applying_preset"] = False


def _coefficients_edited(settings, _context):
    # Typing a coefficient by hand makes the material custom.
    if not settings.get("_applying_preset", False) and settings.preset != "CUSTOM":
        settings.preset = "CUSTOM"


PRESET_ITEMS = [(key, label, f"Measured {label} (Jensen et al. 2001)")
                for key, (label, _s, _a) in presets.MEASURED_MEDIA.items()]
PRESET_ITEMS.append(("CUSTOM", "Custom", "Coefficients typed by hand"))


class SubsplatMaterialSettings(bpy.types.PropertyGroup):
    enabled: BoolProperty(name="Translucent", default=False,
                          description="Render this material with subsurface scattering")
    source: EnumProperty(name="Source", default="DIPOLE", items=[
        ("DIPOLE", "Dipole", "Homogeneous material from absorption and reduced scattering coefficients"),
        ("SUBEDIT_FILE", "SubEdit File",
         "Heterogeneous material: a scattering profile per texel, mapped by the UV map used for rendering, "
         "from a SubEdit file (OpenEXR; docs/SUBEDIT_FILE.md)"),
        ("PRINCIPLED", "Principled BSDF",
         "From the material's Principled BSDF: subsurface colour as the diffuse albedo and subsurface radius "
         "(scene units) as the mean free path; image textures connected to them vary it per texel "
         "(docs/PRINCIPLED.md)"),
        ("ARTIST", "Artist",
         "A radius of influence and a translucency image (the light carried over distance / radius), with "
         "an albedo colour or image applied at entry and exit (docs/ARTIST.md)")])
    artist_radius: FloatProperty(
        name="Radius of Influence", default=0.1, min=0.0, soft_min=1e-4, soft_max=10.0, precision=4, subtype="DISTANCE",
        description="Artist: how far light travels under the surface, in scene units (the translucency image "
                    "spans 0 to this distance)")
    translucency_image: PointerProperty(
        name="Translucency", type=bpy.types.Image,
        description="Artist: a 1D image (its middle row) of the light carried from a point to another at "
                    "distance / radius from 0 (left) to 1 (right), per colour; only its shape matters")
    albedo_color: FloatVectorProperty(
        name="Albedo", size=3, subtype="COLOR", default=(0.8, 0.8, 0.8), min=0.0, max=1.0,
        description="Artist: how much of the light entering comes back out, per colour")
    albedo_image: PointerProperty(
        name="Albedo Image", type=bpy.types.Image,
        description="Artist: the albedo per texel, by the render UV map (replaces the colour)")
    subedit_path: StringProperty(
        name="File", default="", subtype="FILE_PATH",
        description="SubEdit material file (OpenEXR with channels P0.R ... Pn.B holding ln P per texel); "
                    "relative paths ('//') start at the .blend file")
    fit_tolerance: FloatProperty(
        name="Fit Tolerance", default=0.01, min=1e-6, max=1.0, soft_min=1e-4, soft_max=0.1, precision=4, step=0.01,
        description="Largest mean energy error the material's model may make against its source: fewer "
                    "segments and profiles when larger (faster to set up, less GPU memory)")
    preset: EnumProperty(name="Preset", items=PRESET_ITEMS, default="MARBLE", update=_apply_preset,
                         description="Measured scattering coefficients")
    sigma_a: FloatVectorProperty(name="Absorption", size=3, min=0.0, max=1e4, precision=4, step=0.01,
                                 default=presets.MEASURED_MEDIA["MARBLE"][2], update=_coefficients_edited,
                                 description="Absorption coefficient sigma_a per millimetre (RGB)")
    sigma_s_prime: FloatVectorProperty(name="Reduced Scattering", size=3, min=0.0, max=1e4, precision=3,
                                       default=presets.MEASURED_MEDIA["MARBLE"][1], update=_coefficients_edited,
                                       description="Reduced scattering coefficient sigma_s' per millimetre (RGB)")
    eta: FloatProperty(name="IOR", default=presets.MEASURED_ETA, min=1.0, max=3.0,
                       description="Relative index of refraction")
    profile_model: EnumProperty(name="Profile Model", default="TABULATED", items=[
        ("TABULATED", "Tabulated Transport",
         "The half-space's scattering profile and angular factors and thin slabs' transmission, tabulated "
         "from exact solutions of light transport (docs/TRANSPORT.md); matches path-traced truth on slabs "
         "and thin parts"),
        ("DIPOLE", "Classical Dipole",
         "The dipole diffusion model of Jensen et al. 2001, the paper's: no direction, no thin parts")],
        description="The model a homogeneous medium's translucency comes from (absorption and scattering "
                    "coefficients, Principled BSDF)")
    mm_per_unit: FloatProperty(name="Millimetres per Unit", default=1000.0, min=1e-6, max=1e9, soft_min=0.1,
                               soft_max=10000.0,
                               description="Scale of the scene: millimetres in one Blender unit (1000 when 1 unit is 1 m)")
    roughness: FloatProperty(name="Roughness", default=0.3, min=0.0, max=1.0, subtype="FACTOR")
    specular: FloatProperty(name="Specular", default=0.5, min=0.0, max=1.0, subtype="FACTOR")


CLASSES = (SubsplatSceneSettings, SubsplatMaterialSettings)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.subsplat = PointerProperty(type=SubsplatSceneSettings)
    bpy.types.Material.subsplat = PointerProperty(type=SubsplatMaterialSettings)


def unregister():
    del bpy.types.Material.subsplat
    del bpy.types.Scene.subsplat
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
