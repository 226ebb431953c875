# blender -b --python cycles_render.py -- SCENE.gltf OUT.exr SUN_DIR_X,Y,Z(glTF, direction of travel) STRENGTH SAMPLES WIDTH HEIGHT EYE_X,Y,Z TGT_X,Y,Z FOV_DEG
# Cycles reference for bench/burley_cycles (run.sh calls it): direct light only (max bounces 0),
# one sun of angle 0 (hard shadows) and no world light; writes Combined, DiffDir, DiffCol and IndexOB.
import bpy, sys, math
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool, gone in numpy >= 1.24
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
scene_path, out = a[0], a[1]
vec = lambda s: [float(v) for v in s.split(",")]
gl2bl = lambda v: Vector((v[0], -v[2], v[1]))     # glTF Y-up -> Blender Z-up
sun_dir, strength, samples, width, height = gl2bl(vec(a[2])).normalized(), float(a[3]), int(a[4]), int(a[5]), int(a[6])
eye, tgt, fov = gl2bl(vec(a[7])), gl2bl(vec(a[8])), float(a[9])

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=scene_path)
idx = {"sphere_r0": 1, "sphere_r05": 2, "sphere_r1": 3, "floor": 4}   # = dhdr's id.object order
for ob in list(sc.objects):
    if ob.type == "MESH":
        ob.pass_index = idx.get(ob.name, 9)
        m = ob.active_material.node_tree.nodes.get("Principled BSDF") if ob.active_material else None
        print("mesh", ob.name, ob.pass_index, "smooth", all(p.use_smooth for p in ob.data.polygons),
              m and [(k, tuple(m.inputs[k].default_value) if hasattr(m.inputs[k].default_value, "__len__")
                      else round(m.inputs[k].default_value, 4))
                     for k in ("Base Color", "Metallic", "Roughness", "Specular", "Subsurface", "Sheen", "Clearcoat", "Transmission")],
              m and m.distribution)
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

ld = bpy.data.lights.new("sun", "SUN"); ld.energy = strength; ld.angle = 0.0
sun = bpy.data.objects.new("sun", ld); sc.collection.objects.link(sun)
sun.rotation_mode = "QUATERNION"
sun.rotation_quaternion = sun_dir.to_track_quat("-Z", "Y")     # a sun shines along its -Z

w = bpy.data.worlds.new("black"); sc.world = w; w.use_nodes = True
w.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0

r = sc.render
r.engine = "CYCLES"
c = sc.cycles
c.device = "CPU"; c.samples = samples; c.use_adaptive_sampling = False; c.use_denoising = False; c.seed = 1
c.max_bounces = 0; c.diffuse_bounces = 0; c.glossy_bounces = 0; c.transmission_bounces = 0
c.caustics_reflective = c.caustics_refractive = False
c.pixel_filter_type = "BOX"; c.filter_width = 1.0
r.film_transparent = True
r.resolution_x, r.resolution_y = width, height; r.resolution_percentage = 100
r.threads_mode = "FIXED"; r.threads = 2
vl = sc.view_layers[0]
vl.use_pass_object_index = True
vl.use_pass_diffuse_direct = True; vl.use_pass_diffuse_color = True
vl.use_pass_glossy_direct = True; vl.use_pass_normal = True
r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
r.image_settings.color_depth = "32"; r.image_settings.exr_codec = "ZIP"
r.filepath = out
bpy.ops.render.render(write_still=True)
