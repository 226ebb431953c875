# blender -b --python cycles_render.py -- SCENE.gltf OUT.exr HDRI SAMPLES WIDTH HEIGHT EYE_X,Y,Z TGT_X,Y,Z FOV_DEG
# Cycles reference for bench/sheen_cycles (run.sh calls it): Blender 3.4's glTF importer turns
# KHR_materials_sheen into a Velvet BSDF (colour sheenColorFactor, sigma sheenRoughnessFactor)
# added to the Principled BSDF. The world is the HDRI at strength 1 with no mapping (dhdr's
# equirect orientation, docs/ibl.md); the spheres are visible to camera rays only, so that each
# sees the whole HDRI as dhdr without --scene does. Box filter 1 px, no denoising, no clamping.
import bpy, sys, math
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
scene_path, out, hdri = a[0], a[1], a[2]
samples, width, height = int(a[3]), int(a[4]), int(a[5])
vec = lambda s: [float(v) for v in s.split(",")]
gl2bl = lambda v: Vector((v[0], -v[2], v[1]))     # glTF Y-up -> Blender Z-up
eye, tgt, fov = gl2bl(vec(a[6])), gl2bl(vec(a[7])), float(a[8])

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=scene_path)
for ob in list(sc.objects):
    if ob.type == "MESH":
        ob.visible_diffuse = ob.visible_glossy = ob.visible_transmission = False
        ob.visible_volume_scatter = ob.visible_shadow = False
        nodes = ob.active_material.node_tree.nodes
        velvet = [n for n in nodes if n.type == "BSDF_VELVET"]
        print("mesh", ob.name, "velvet", velvet and (tuple(round(x, 3) for x in velvet[0].inputs[0].default_value),
                                                    round(velvet[0].inputs[1].default_value, 3)))
        nodes.get("Principled BSDF").distribution = "MULTI_GGX"
    elif ob.type in ("CAMERA", "LIGHT"):
        bpy.data.objects.remove(ob)

camd = bpy.data.cameras.new("cam"); cam = bpy.data.objects.new("cam", camd)
sc.collection.objects.link(cam)
cam.location = eye
cam.rotation_mode = "QUATERNION"
cam.rotation_quaternion = (tgt - eye).to_track_quat("-Z", "Y")
camd.sensor_fit = "VERTICAL"; camd.angle_y = math.radians(fov)
camd.clip_start = 0.01; camd.clip_end = 1000
sc.camera = cam

w = bpy.data.worlds.new("w"); sc.world = w; w.use_nodes = True
nt = w.node_tree; nt.nodes.clear()
env = nt.nodes.new("ShaderNodeTexEnvironment"); bg = nt.nodes.new("ShaderNodeBackground")
wo = nt.nodes.new("ShaderNodeOutputWorld")
env.image = bpy.data.images.load(hdri); env.interpolation = "Linear"
bg.inputs["Strength"].default_value = 1.0
nt.links.new(env.outputs["Color"], bg.inputs["Color"])
nt.links.new(bg.outputs["Background"], wo.inputs["Surface"])
w.cycles.sampling_method = "MANUAL"; w.cycles.sample_map_resolution = 4096

r = sc.render
r.engine = "CYCLES"
c = sc.cycles
c.device = "CPU"; c.samples = samples; c.use_adaptive_sampling = False; c.use_denoising = False; c.seed = 1
c.max_bounces = 1; c.diffuse_bounces = 1; c.glossy_bounces = 1; c.transmission_bounces = 0
c.sample_clamp_direct = 0.0; c.sample_clamp_indirect = 0.0
c.pixel_filter_type = "BOX"; c.filter_width = 1.0
r.film_transparent = True
r.resolution_x, r.resolution_y = width, height; r.resolution_percentage = 100
r.threads_mode = "FIXED"; r.threads = 2
r.image_settings.file_format = "OPEN_EXR"
r.image_settings.color_depth = "32"; r.image_settings.exr_codec = "ZIP"
r.filepath = out
bpy.ops.render.render(write_still=True)
