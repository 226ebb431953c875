# blender -b --python cycles_render.py -- SCENE.gltf OUT.exr HDRI SAMPLES SEED WIDTH HEIGHT EYE_X,Y,Z TGT_X,Y,Z FOV_DEG
# Cycles reference for bench/metals_cycles (run.sh calls it): the world is the HDRI at strength 1
# with no mapping (dhdr's equirect orientation at rotation 0, docs/ibl.md), Principled BSDF set to
# Multiscatter GGX; every sphere is visible to camera rays only (not to diffuse, glossy,
# transmission or shadow rays), so that each sees the whole, unoccluded HDRI as dhdr without
# --scene does. No clamping, box filter 1 px, no denoising. Writes Combined and IndexOB.
import bpy, sys, math, os
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool, gone in numpy >= 1.24
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
scene_path, out, hdri = a[0], a[1], a[2]
samples, seed, width, height = int(a[3]), int(a[4]), int(a[5]), int(a[6])
vec = lambda s: [float(v) for v in s.split(",")]
gl2bl = lambda v: Vector((v[0], -v[2], v[1]))     # glTF Y-up -> Blender Z-up
eye, tgt, fov = gl2bl(vec(a[7])), gl2bl(vec(a[8])), float(a[9])

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=scene_path)
idx = {"sphere_r0": 1, "sphere_r025": 2, "sphere_r05": 3, "sphere_r075": 4, "sphere_r1": 5}  # = dhdr's id.object
for ob in list(sc.objects):
    if ob.type == "MESH":
        ob.pass_index = idx.get(ob.name, 9)
        ob.visible_diffuse = ob.visible_glossy = ob.visible_transmission = False
        ob.visible_volume_scatter = ob.visible_shadow = False
        m = ob.active_material.node_tree.nodes.get("Principled BSDF")
        m.distribution = os.environ.get("DHDR_CYCLES_DISTRIBUTION", "MULTI_GGX")   # GGX: single scattering (diagnosis)
        print("mesh", ob.name, ob.pass_index, "smooth", all(p.use_smooth for p in ob.data.polygons),
              [(k, tuple(round(x, 4) for x in m.inputs[k].default_value) if hasattr(m.inputs[k].default_value, "__len__")
                else round(m.inputs[k].default_value, 4))
               for k in ("Base Color", "Metallic", "Roughness", "Specular", "Specular Tint", "Anisotropic", "Clearcoat", "Sheen")],
              m.distribution)
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
w.cycles.sampling_method = "MANUAL"
# The importance map at 4096 (not the HDRI's 1024): at 1024 sunrise's 3-texel sun was missed by light
# sampling and found by BSDF rays, fireflies: two seeds' sphere means differed by up to 17 % at 512 spp.
w.cycles.sample_map_resolution = int(os.environ.get("DHDR_CYCLES_MAPRES", "4096"))

# Diagnosis (diag_sun.py): DHDR_CYCLES_SUN=DX,DY,DZ (glTF, direction of travel): the world black and one sun
# lamp of 1 W/m^2 and angle 0 instead, as dhdr's directional light of intensity 1 without --radiometric.
if os.environ.get("DHDR_CYCLES_SUN"):
    bg.inputs["Strength"].default_value = 0.0
    ld = bpy.data.lights.new("sun", "SUN"); ld.energy = 1.0; ld.angle = 0.0
    sun = bpy.data.objects.new("sun", ld); sc.collection.objects.link(sun)
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = gl2bl(vec(os.environ["DHDR_CYCLES_SUN"])).normalized().to_track_quat("-Z", "Y")

r = sc.render
r.engine = "CYCLES"
c = sc.cycles
c.device = "CPU"; c.samples = samples; c.use_adaptive_sampling = False; c.use_denoising = False; c.seed = seed
c.max_bounces = 1; c.diffuse_bounces = 1; c.glossy_bounces = 1; c.transmission_bounces = 0
c.sample_clamp_direct = 0.0; c.sample_clamp_indirect = 0.0
c.pixel_filter_type = "BOX"; c.filter_width = 1.0
r.film_transparent = True
r.resolution_x, r.resolution_y = width, height; r.resolution_percentage = 100
r.threads_mode = "FIXED"; r.threads = 2
vl = sc.view_layers[0]
vl.use_pass_object_index = True
r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
r.image_settings.color_depth = "32"; r.image_settings.exr_codec = "ZIP"
r.filepath = out
bpy.ops.render.render(write_still=True)
