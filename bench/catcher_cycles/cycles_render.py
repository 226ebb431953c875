# blender -b --python cycles_render.py -- OUT.exr MAPPING_Z_DEG SAMPLES DENOISE(0|1) [VARIANT]
# (run.sh calls it; SCENE and HDRI come from the environment variables DHDR_SCENE, DHDR_HDRI)
# VARIANT: pass = also write the Shadow Catcher pass (combined alpha then holds no shadow);
#          noplane = the catcher is invisible to diffuse/glossy/transmission rays (spheres see the HDRI's lower half, as in dhdr)
import bpy, sys, math, os
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool, gone in numpy >= 1.24
from mathutils import Vector
argv = sys.argv[sys.argv.index("--") + 1:]
out, rotz, samples, denoise = argv[0], float(argv[1]), int(argv[2]), argv[3] == "1"
variant = argv[4] if len(argv) > 4 else ""

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=os.environ["DHDR_SCENE"])
idx = {"gold_sphere": 1, "red_sphere": 2, "white_sphere": 3}
for ob in sc.objects:
    if ob.type == "MESH":
        ob.pass_index = idx.get(ob.name, 9)
        print("mesh", ob.name, [tuple(round(c, 3) for c in ob.matrix_world @ Vector(b)) for b in (ob.bound_box[0], ob.bound_box[6])])
# catcher: large plane at the glTF ground height y = 0 (Blender z = 0), white 0.8 diffuse
bpy.ops.mesh.primitive_plane_add(size=200, location=(0, 0, 0))
plane = bpy.context.active_object
plane.name = "catcher"
plane.is_shadow_catcher = True
plane.pass_index = 4
m = bpy.data.materials.new("catcher_mat"); m.use_nodes = True
p = m.node_tree.nodes["Principled BSDF"]
p.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1); p.inputs["Roughness"].default_value = 1.0
p.inputs["Specular"].default_value = 0.0
plane.data.materials.append(m)

# camera: glTF eye (0.6,0.9,3.6) target (0.3,0.35,0) -> Blender (x,-z,y)
eye, tgt = Vector((0.6, -3.6, 0.9)), Vector((0.3, 0.0, 0.35))
camd = bpy.data.cameras.new("cam"); cam = bpy.data.objects.new("cam", camd)
sc.collection.objects.link(cam)
cam.location = eye
cam.rotation_mode = "QUATERNION"
cam.rotation_quaternion = (tgt - eye).to_track_quat("-Z", "Y")
camd.sensor_fit = "VERTICAL"; camd.angle_y = math.radians(39.6)
camd.clip_start = 0.01; camd.clip_end = 1000
sc.camera = cam
for ob in list(sc.objects):
    if ob.type == "CAMERA" and ob is not cam:
        bpy.data.objects.remove(ob)

# world: equirect HDRI, mapping rotation about Z
w = bpy.data.worlds.new("w"); sc.world = w; w.use_nodes = True
nt = w.node_tree; nt.nodes.clear()
tc = nt.nodes.new("ShaderNodeTexCoord"); mp = nt.nodes.new("ShaderNodeMapping")
env = nt.nodes.new("ShaderNodeTexEnvironment"); bg = nt.nodes.new("ShaderNodeBackground")
wo = nt.nodes.new("ShaderNodeOutputWorld")
env.image = bpy.data.images.load(os.environ["DHDR_HDRI"])
env.interpolation = "Linear"
mp.vector_type = "POINT"; mp.inputs["Rotation"].default_value = (0, 0, math.radians(rotz))
nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
nt.links.new(mp.outputs["Vector"], env.inputs["Vector"])
nt.links.new(env.outputs["Color"], bg.inputs["Color"])
nt.links.new(bg.outputs["Background"], wo.inputs["Surface"])

r = sc.render
r.engine = "CYCLES"
sc.cycles.device = "CPU"
sc.cycles.samples = samples
sc.cycles.use_adaptive_sampling = False
sc.cycles.use_denoising = denoise
sc.cycles.seed = 1
sc.cycles.pixel_filter_type = "BOX"; sc.cycles.filter_width = 1.0
r.film_transparent = True
r.resolution_x, r.resolution_y, r.resolution_percentage = 480, 270, 100
r.threads_mode = "FIXED"; r.threads = 2
vl = sc.view_layers[0]
vl.use_pass_object_index = True
vl.cycles.use_pass_shadow_catcher = variant == "pass"   # off: the approximate shadow goes into the combined alpha
if variant == "noplane":
    plane.visible_diffuse = plane.visible_glossy = plane.visible_transmission = False
r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
r.image_settings.color_depth = "32"
r.image_settings.exr_codec = "ZIP"
r.filepath = out
print("blur_glossy", sc.cycles.blur_glossy, "max_bounces", sc.cycles.max_bounces)
bpy.ops.render.render(write_still=True)
