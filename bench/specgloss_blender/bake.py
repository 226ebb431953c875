"""Run by Blender (blender -b --python bake.py -- scene.gltf out_prefix): imports the glTF file
(the square of compare.py) with Blender's own importer and renders with Cycles, head-on through
an orthographic camera that the square fills (64 x 64), what the material's node tree feeds the
Glossy BSDF's Color and Roughness and the Diffuse BSDF's Color: each source linked in turn to an
Emission shader, so that Blender evaluates its own texture decoding and factor nodes. Writes
out_prefix_{glossy,roughness,diffuse}.exr (linear)."""
import sys

import bpy
import numpy

if not hasattr(numpy, "bool"):
    numpy.bool = bool  # the Debian glTF importer (3.4) uses np.bool, gone in numpy >= 1.24

gltf, prefix = sys.argv[sys.argv.index("--") + 1:][:2]
# "packed": the images' alpha as Blender's Channel Packed mode reads it, a channel apart from the
# colour (as the glTF extension means it); else as the importer leaves them (straight alpha, which
# Blender premultiplies into the 8-bit colour before its sRGB decode).
packed = "packed" in sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=gltf)
obj = next(o for o in bpy.context.scene.objects if o.type == "MESH")
bpy.context.view_layer.objects.active = obj
obj.select_set(True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.samples = 1
scene.cycles.device = "CPU"
scene.cycles.use_denoising = False
if packed:
    for image in bpy.data.images:
        image.alpha_mode = "CHANNEL_PACKED"
mat = obj.material_slots[0].material
nodes, links = mat.node_tree.nodes, mat.node_tree.links
glossy = next(n for n in nodes if n.type == "BSDF_GLOSSY")
diffuse = next(n for n in nodes if n.type == "BSDF_DIFFUSE")
output = next(n for n in nodes if n.type == "OUTPUT_MATERIAL" and n.is_active_output)
emission = nodes.new("ShaderNodeEmission")
emission.inputs["Strength"].default_value = 1.0
links.new(output.inputs["Surface"], emission.outputs[0])
# glTF's +Z (towards the viewer) is Blender's -Y: the camera at y = -3 looks along +Y.
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.data.type = "ORTHO"
camera.data.ortho_scale = 2.0
camera.location = (0.0, -3.0, 0.0)
camera.rotation_euler = (1.5707963267948966, 0.0, 0.0)
scene.camera = camera
scene.render.resolution_x = scene.render.resolution_y = 64
scene.render.resolution_percentage = 100
scene.cycles.filter_width = 0.01
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
for name, socket in [("glossy", glossy.inputs["Color"]), ("roughness", glossy.inputs["Roughness"]),
                     ("diffuse", diffuse.inputs["Color"])]:
    for link in list(emission.inputs["Color"].links):
        links.remove(link)
    if socket.links:
        source = socket.links[0].from_socket
        # Blender 3.4's importer links the Specular Factor Mix node (RGBA) by its Float output,
        # which that mode disables: Cycles then renders the glossy colour 1. The Color output of
        # the same node is what the importer means.
        if not source.enabled:
            source = next(o for o in source.node.outputs if o.enabled and o.name == source.name)
            print(f"compare: {name}: the importer linked a disabled output; its Color one used")
        links.new(emission.inputs["Color"], source)
    else:
        v = socket.default_value
        emission.inputs["Color"].default_value = (list(v)[:3] if hasattr(v, "__len__") else [v] * 3) + [1]
    scene.render.filepath = f"{prefix}_{name}.exr"
    bpy.ops.render.render(write_still=True)
