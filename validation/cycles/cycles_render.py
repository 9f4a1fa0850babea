# Renders a shvol scene with Blender Cycles (run by Blender 3.4:
#   blender -b --factory-startup --python cycles_render.py -- SCENE.json OUT.exr SPP SEED THREADS
# ). SCENE.json is a resolved shvol scene (the "scene_resolved" of a render's stats, with the
# scene's directory in "scene_dir"), restricted to what both renderers share: a perspective
# camera, a constant environment or a lat-long image in Blender's mapping, and VDB media with
# albedo, Henyey-Greenstein phase, density scale and a translate/scale transform. It prints one
# line "CYCLES_TIME <seconds>" with the wall time of the render call (scene synchronisation
# included).
#
# How the scene maps onto Cycles:
# - Principled Volume: scattering = density * color and absorption = density * (1 - color) (with
#   the default black absorption color), so color = albedo and density = density_scale gives
#   sigma_t = density_scale * grid value per scene unit, as in shvol. Anisotropy = g.
# - Cycles puts a VDB voxel's value half a voxel further along +x, +y, +z than OpenVDB's
#   BoxSampler (which shvol follows, DESIGN.md): the volume object is moved back by half a voxel
#   (in scene units, after the medium's scale) so the two densities coincide.
# - The camera's vertical field of view; a 1-pixel box filter (shvol jitters uniformly within the
#   pixel); no adaptive sampling, denoising or clamping; volume bounces = max_depth; the view
#   transform Standard so the EXR holds the linear radiance.
import json
import math
import os
import sys
import time

import bpy
import mathutils

args = sys.argv[sys.argv.index("--") + 1:]
scene_file, out, spp, seed, threads = args[0], args[1], int(args[2]), int(args[3]), int(args[4])
doc = json.load(open(scene_file))
base = doc.get("scene_dir", os.path.dirname(os.path.abspath(scene_file)))

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

cam_doc = doc["camera"]
if cam_doc.get("type", "perspective") != "perspective":
    sys.exit("only perspective cameras")
cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(cam_doc["fov"])
cam_data.clip_start = 1e-4
cam_data.clip_end = 1e6
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
position = mathutils.Vector(cam_doc["position"])
forward = (mathutils.Vector(cam_doc["target"]) - position).normalized()
up = mathutils.Vector(cam_doc["up"])
right = forward.cross(up).normalized()
true_up = right.cross(forward)
# Blender cameras look along local -Z with local +Y up.
rot = mathutils.Matrix((right, true_up, -forward)).transposed()
cam.matrix_world = mathutils.Matrix.Translation(position) @ rot.to_4x4()
scene.camera = cam
scene.render.resolution_x, scene.render.resolution_y = cam_doc["resolution"]
scene.render.resolution_percentage = 100
scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1

env = doc["environment"]
world = bpy.data.worlds.new("world")
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
if env.get("lower_hemisphere_black", False):
    sys.exit("only environments without a black lower hemisphere")
if env["type"] == "constant":
    radiance = env["radiance"]
    rgb = radiance if isinstance(radiance, list) else [radiance] * 3
    bg.inputs["Color"].default_value = (*rgb, 1.0)
    bg.inputs["Strength"].default_value = 1.0
elif env["type"] == "image":
    # shvol's "blender" mapping is Cycles' equirectangular layout (README, "Lat-long mapping"),
    # and shvol reads the texel a direction falls in, without filtering: "Closest".
    if env.get("mapping", "blender") != "blender" or env.get("rotation", 0) != 0:
        sys.exit("only lat-long images in the blender mapping, not rotated")
    scale = env.get("scale", 1.0)
    if isinstance(scale, list):
        sys.exit("only a scalar environment scale")
    tex = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(os.path.join(base, env["file"]))
    tex.image.colorspace_settings.name = "Linear"
    tex.interpolation = "Closest"
    tex.projection = "EQUIRECTANGULAR"
    world.node_tree.links.new(tex.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = scale
else:
    sys.exit("only constant and lat-long image environments")
scene.world = world

for i, m in enumerate(doc["media"]):
    if m["type"] != "vdb" or m["phase"]["type"] != "hg":
        sys.exit("only VDB media with HG phase functions")
    t = m.get("transform", {})
    if set(t) - {"translate", "scale"}:
        sys.exit("only translate/scale transforms")
    scale = t.get("scale", 1.0)
    scale = scale if isinstance(scale, list) else [scale] * 3
    vdb = bpy.data.volumes.new("medium%d" % i)
    vdb.filepath = os.path.join(base, m["file"])
    # Full-precision voxels (Cycles' default is half floats) and no clipping (by default voxels
    # below 0.001 are left out of the volume's bounding mesh, so their density is lost).
    vdb.render.precision = "FULL"
    vdb.render.clipping = 0.0
    # Density per scene unit, as shvol's density_scale (Cycles' default is per object-space
    # unit: divided by the object's scale).
    vdb.render.space = "WORLD"
    vdb.grids.load()
    grid = vdb.grids[m["grid"]]
    voxel = [grid.matrix_object.col[a].length for a in range(3)]
    obj = bpy.data.objects.new("medium%d" % i, vdb)
    scene.collection.objects.link(obj)
    obj.scale = scale
    obj.location = [t.get("translate", [0, 0, 0])[a] - 0.5 * voxel[a] * scale[a] for a in range(3)]
    mat = bpy.data.materials.new("medium%d" % i)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        nodes.remove(n)
    pv = nodes.new("ShaderNodeVolumePrincipled")
    outn = nodes.new("ShaderNodeOutputMaterial")
    mat.node_tree.links.new(pv.outputs["Volume"], outn.inputs["Volume"])
    albedo = m["albedo"] if isinstance(m["albedo"], list) else [m["albedo"]] * 3
    pv.inputs["Color"].default_value = (*albedo, 1.0)
    pv.inputs["Density"].default_value = m["density_scale"]
    pv.inputs["Density Attribute"].default_value = m["grid"]
    pv.inputs["Anisotropy"].default_value = m["phase"]["g"]
    vdb.materials.append(mat)

c = scene.cycles
scene.render.engine = "CYCLES"
c.device = "CPU"
c.samples = spp
c.seed = seed
c.use_animated_seed = False
c.use_adaptive_sampling = False
c.use_denoising = False
c.sample_clamp_direct = 0
c.sample_clamp_indirect = 0
depth = min(doc["render"]["max_depth"], 1024)  # Cycles allows at most 1024 bounces
c.max_bounces = depth
c.volume_bounces = depth
c.transparent_max_bounces = depth
c.pixel_filter_type = "BOX"
c.filter_width = 1.0
scene.render.film_transparent = False
scene.render.threads_mode = "FIXED"
scene.render.threads = threads
scene.render.use_persistent_data = False
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0
scene.view_settings.gamma = 1
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.exr_codec = "ZIP"
scene.render.filepath = out
start = time.time()
bpy.ops.render.render(write_still=True)
print("CYCLES_TIME %.6f" % (time.time() - start))
