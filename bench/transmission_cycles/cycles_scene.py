# blender -b --python cycles_scene.py -- WORK_DIR HDRI SAMPLES WIDTH HEIGHT SUN_E [direct|nocaustics|gi]
# bench/transmission_cycles (run.sh calls it): builds the scene in Blender 3.4, exports it with
# Blender's own glTF exporter (WORK_DIR/scene.glb: KHR_materials_transmission from the Principled
# BSDF's Transmission) and renders it with Cycles (WORK_DIR/cycles.exr; cycles_MODE.exr otherwise).
# Geometry (Blender, Z up; glTF is (x, z, -y)); analyze.py ray-casts the same numbers:
#   floor z = 0, x in [-3, 3], y in [-0.3, 3] (grey 0.5, roughness 0.8); it stops just in front
#     of the panes, so that their mirror images are of the HDRI and not of a floor;
#   back wall y = 3, x in [-3, 3], z in [0, 2.5], a checker (sRGB 0.8 / 0.1, 0.25 m cells);
#   three panes, thin boxes 1.0 (x) x 0.01 (y) x 1.4 (z) standing on the floor at y = 0,
#     x centres -1.2, 0, 1.2: A clear (base 1), roughness 0; B tinted (0.9, 0.55, 0.2),
#     roughness 0; C clear, roughness 0.3. Principled BSDF, Transmission 1, IOR 1.5,
#     Specular 0.5 (F0 0.04), Multiscatter GGX;
#   spheres of radius 0.3 on the floor at y = 1.5 behind each pane (red, white, blue) and one
#     unobstructed green one at (2.3, 1.0);
#   a sun of SUN_E W/m^2, angle 0, travelling along (0.35, 0.8, -1) (from behind the camera,
#     so each pane's shadow falls on the floor behind it), and the HDRI as the world
#     (strength 1, no mapping: dhdr's equirect orientation, docs/ibl.md).
# Cycles, direct light (as dhdr --gi direct): diffuse bounces 0, glossy 1 (the panes' mirror
# images), transmission 8 (through the two faces of each pane), box filter 1 px, no denoising,
# no clamping. Variants: nocaustics (caustics off), nomis (the world not light-sampled: the sky
# only through BSDF-sampled rays), sunonly (world strength 0), opaquepanes (black panes of
# transmission 0 and roughness 1), gi (diffuse 4, glossy 4).
import bpy, sys, math, os
import numpy as np
if not hasattr(np, "bool"): np.bool = bool  # the Debian glTF add-on (3.4) uses np.bool
from mathutils import Vector
a = sys.argv[sys.argv.index("--") + 1:]
work, hdri = a[0], a[1]
samples, width, height, sun_e = int(a[2]), int(a[3]), int(a[4]), float(a[5])
mode = a[6] if len(a) > 6 else "direct"     # direct | nocaustics | nomis | sunonly | opaquepanes | gi
gi = mode == "gi"

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene


def principled(name, base, rough, transmission=0.0, image=None):
    m = bpy.data.materials.new(name); m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.distribution = "MULTI_GGX"
    p.inputs["Base Color"].default_value = (*base, 1)
    p.inputs["Roughness"].default_value = rough
    p.inputs["Metallic"].default_value = 0.0
    p.inputs["Specular"].default_value = 0.5
    p.inputs["IOR"].default_value = 1.5
    p.inputs["Transmission"].default_value = transmission
    if image is not None:
        t = m.node_tree.nodes.new("ShaderNodeTexImage"); t.image = image; t.interpolation = "Closest"
        m.node_tree.links.new(t.outputs["Color"], p.inputs["Base Color"])
    return m


def add(ob, name, mat, index):
    ob.name = name; ob.data.name = name
    ob.data.materials.append(mat); ob.pass_index = index
    return ob


# Checker for the wall: 480 x 200 texels over 6 x 2.5 m, 20-texel (0.25 m) cells, sRGB 0.8 / 0.1.
W, H = 480, 200
yy, xx = np.mgrid[0:H, 0:W]
v = np.where(((xx // 20) + (yy // 20)) % 2 == 0, 0.8, 0.1).astype(np.float32)
img = bpy.data.images.new("checker", W, H, alpha=False)
px = np.ones((H, W, 4), np.float32); px[..., 0] = px[..., 1] = px[..., 2] = v
img.pixels.foreach_set(px.ravel())
img.filepath_raw = os.path.join(work, "checker.png"); img.file_format = "PNG"; img.save()

bpy.ops.mesh.primitive_plane_add(size=1, location=(0, 1.35, 0))
fl = add(bpy.context.object, "floor", principled("floor", (0.5, 0.5, 0.5), 0.8), 1)
fl.scale = (6, 3.3, 1)
bpy.ops.mesh.primitive_plane_add(size=1, location=(0, 3, 1.25), rotation=(math.pi / 2, 0, 0))
wl = add(bpy.context.object, "wall", principled("wall", (1, 1, 1), 0.8, image=img), 2)
wl.scale = (6, 2.5, 1)
PANES = [("paneA_clear_r0", -1.2, (1, 1, 1), 0.0), ("paneB_tint_r0", 0.0, (0.9, 0.55, 0.2), 0.0),
         ("paneC_clear_r03", 1.2, (1, 1, 1), 0.3)]
for k, (n, x, base, rough) in enumerate(PANES):
    bpy.ops.mesh.primitive_cube_add(size=1, location=(x, 0, 0.7))
    if mode == "opaquepanes":   # after the export: black, non-transmissive panes (their shadows opaque)
        base, rough = (0, 0, 0), 1.0
    ob = add(bpy.context.object, n, principled(n, base, rough, transmission=0.0 if mode == "opaquepanes" else 1.0), 3 + k)
    ob.scale = (1.0, 0.01, 1.4)
SPHERES = [("sphere_red", (-1.2, 1.5), (0.8, 0.1, 0.1)), ("sphere_white", (0.0, 1.5), (0.8, 0.8, 0.8)),
           ("sphere_blue", (1.2, 1.5), (0.1, 0.2, 0.8)), ("sphere_green", (2.3, 1.0), (0.1, 0.7, 0.2))]
for k, (n, (x, y), c) in enumerate(SPHERES):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=0.3, location=(x, y, 0.3))
    bpy.ops.object.shade_smooth()
    add(bpy.context.object, n, principled(n, c, 0.4), 6 + k)
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.transform_apply(location=False, rotation=True, scale=True)

glb = os.path.join(work, "scene.glb")
if mode == "direct":
    bpy.ops.export_scene.gltf(filepath=glb, export_format="GLB", export_cameras=False,
                              export_lights=False, export_apply=True)

# Camera: glTF eye (0, 2.0, 4.5), target (0, 0.45, -1.2), vertical fov 40 degrees (run.sh's --lookat).
eye, tgt = Vector((0, -4.5, 2.0)), Vector((0, 1.2, 0.45))
camd = bpy.data.cameras.new("cam"); cam = bpy.data.objects.new("cam", camd)
sc.collection.objects.link(cam)
cam.location = eye; cam.rotation_mode = "QUATERNION"
cam.rotation_quaternion = (tgt - eye).to_track_quat("-Z", "Y")
camd.sensor_fit = "VERTICAL"; camd.angle_y = math.radians(40.0)
camd.clip_start = 0.01; camd.clip_end = 1000
sc.camera = cam

ld = bpy.data.lights.new("sun", "SUN"); ld.energy = sun_e; ld.angle = 0.0
sun = bpy.data.objects.new("sun", ld); sc.collection.objects.link(sun)
sun.rotation_mode = "QUATERNION"
sun.rotation_quaternion = Vector((0.35, 0.8, -1.0)).normalized().to_track_quat("-Z", "Y")

w = bpy.data.worlds.new("w"); sc.world = w; w.use_nodes = True
nt = w.node_tree; nt.nodes.clear()
env = nt.nodes.new("ShaderNodeTexEnvironment"); bg = nt.nodes.new("ShaderNodeBackground")
wo = nt.nodes.new("ShaderNodeOutputWorld")
env.image = bpy.data.images.load(hdri); env.interpolation = "Linear"
bg.inputs["Strength"].default_value = 1.0
nt.links.new(env.outputs["Color"], bg.inputs["Color"])
nt.links.new(bg.outputs["Background"], wo.inputs["Surface"])
w.cycles.sampling_method = "MANUAL"; w.cycles.sample_map_resolution = 2048
if mode == "nomis":      # the sky reached by BSDF-sampled rays only (no light sampling)
    w.cycles.sampling_method = "NONE"
if mode == "sunonly":
    bg.inputs["Strength"].default_value = 0.0

r = sc.render
r.engine = "CYCLES"
c = sc.cycles
c.device = "CPU"; c.samples = samples; c.use_adaptive_sampling = False; c.use_denoising = False; c.seed = 1
c.max_bounces = 12; c.transmission_bounces = 8; c.transparent_max_bounces = 8
c.diffuse_bounces, c.glossy_bounces = (4, 4) if gi else (0, 1)
c.caustics_reflective = c.caustics_refractive = mode != "nocaustics"
c.sample_clamp_direct = 0.0; c.sample_clamp_indirect = 0.0
c.pixel_filter_type = "BOX"; c.filter_width = 1.0
sc.view_settings.view_transform = "Standard"; sc.view_settings.look = "None"
r.film_transparent = False
r.resolution_x, r.resolution_y = width, height; r.resolution_percentage = 100
r.threads_mode = "FIXED"; r.threads = 2
vl = sc.view_layers[0]
vl.use_pass_object_index = True
vl.use_pass_diffuse_direct = vl.use_pass_diffuse_indirect = vl.use_pass_diffuse_color = True
vl.use_pass_glossy_direct = vl.use_pass_glossy_indirect = vl.use_pass_glossy_color = True
vl.use_pass_transmission_direct = vl.use_pass_transmission_indirect = vl.use_pass_transmission_color = True
r.image_settings.file_format = "OPEN_EXR_MULTILAYER"
r.image_settings.color_depth = "32"; r.image_settings.exr_codec = "ZIP"
r.filepath = os.path.join(work, "cycles.exr" if mode == "direct" else "cycles_%s.exr" % mode)
for ob in sc.objects:
    if ob.type == "MESH":
        p = ob.active_material.node_tree.nodes["Principled BSDF"]
        print("mesh", ob.name, ob.pass_index, tuple(round(x, 3) for x in p.inputs["Base Color"].default_value),
              "rough", p.inputs["Roughness"].default_value, "transmission", p.inputs["Transmission"].default_value,
              "ior", p.inputs["IOR"].default_value, p.distribution)
bpy.ops.render.render(write_still=True)
