# blender -b --python blender_pose.py -- SCENE.gltf OUT.exr FRAME EX,EY,EZ TX,TY,TZ FOV_DEG WxH
# Blender's own glTF importer poses the scene at FRAME (24 fps: frame N is time N / 24, as the
# importer keys it) and Cycles writes its Position and Vector passes from a camera at E looking at T
# (glTF's Y-up coordinates; Blender's are (x, -z, y)). run.sh calls it; compare.py reads it.
import bpy, sys, math
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool, gone in numpy >= 1.24
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:]
scene, out, frame = argv[0], argv[1], int(argv[2])
e = [float(v) for v in argv[3].split(",")]
t = [float(v) for v in argv[4].split(",")]
fov = float(argv[5])
w, h = (int(v) for v in argv[6].split("x"))

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
sc.render.fps = 24
sc.render.fps_base = 1.0
bpy.ops.import_scene.gltf(filepath=scene)
for ob in list(sc.objects):
    if ob.type == "CAMERA":
        bpy.data.objects.remove(ob)
eye, tgt = Vector((e[0], -e[2], e[1])), Vector((t[0], -t[2], t[1]))
camd = bpy.data.cameras.new("cam")
cam = bpy.data.objects.new("cam", camd)
sc.collection.objects.link(cam)
cam.location = eye
cam.rotation_mode = "QUATERNION"
cam.rotation_quaternion = (tgt - eye).to_track_quat("-Z", "Y")
camd.sensor_fit = "VERTICAL"
camd.angle_y = math.radians(fov)
camd.clip_start = 0.001
camd.clip_end = 1000
sc.camera = cam
sc.frame_set(frame)

r = sc.render
r.engine = "CYCLES"
sc.cycles.device = "CPU"
sc.cycles.samples = 16
sc.cycles.use_adaptive_sampling = False
sc.cycles.use_denoising = False
sc.cycles.seed = 1
sc.cycles.pixel_filter_type = "BOX"
sc.cycles.filter_width = 1.0
r.film_transparent = True
r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
r.threads_mode = "FIXED"
r.threads = 2
vl = sc.view_layers[0]
vl.use_pass_position = True
vl.use_pass_normal = True
vl.use_pass_vector = True  # Blender's motion vectors (written only without motion blur)
r.use_motion_blur = False
r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
r.image_settings.color_depth = "32"
r.image_settings.exr_codec = "ZIP"
r.filepath = out
bpy.ops.render.render(write_still=True)
