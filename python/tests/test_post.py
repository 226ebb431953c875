"""Bloom and edge AA from Python against dhdr-bloom and dhdr-aa, bit for bit."""
import numpy as np
import pytest

import dhdr
from conftest import hdr_frame, read_file, run_tool, write_exr
from test_tonemap import same_bits


def test_bloom_equals_tool(tmp_path):
    src = write_exr(tmp_path / "in.exr", hdr_frame(extra=2), list("RGBA") + ["AO", "mask"])
    args = ["--threshold", "0.6", "--sigma", "3", "--strength", "0.8", "--key", "0.2"]
    run_tool("dhdr-bloom", src, *args, "-o", tmp_path / "tool.exr")
    mine = dhdr.bloom(dhdr.read(str(src)), threshold=0.6, sigma=3, strength=0.8, key=0.2)
    assert mine.channels == ["R", "G", "B", "A", "AO", "mask"]
    same_bits(mine.pixels, read_file(tmp_path / "tool.exr"))  # float in, float out


def test_bloom_layer_and_dst_form():
    frame = hdr_frame()
    frame[20:28, 30:38, :3] = 500.0  # a light: a block survives the quarter-size bright pass
    img = dhdr.Image(frame)
    layer = dhdr.bloom_layer(img, strength=2.0)
    assert layer.nchannels == 3
    out = dhdr.bloom(img, strength=2.0).pixels
    np.testing.assert_allclose(out[..., :3], img.pixels[..., :3] + 2.0 * layer.pixels, rtol=1e-6)
    # In place: dst is src; the bloom reads its whole source before adding.
    before = img.pixels.copy()
    assert dhdr.bloom(img, img, strength=2.0)
    same_bits(img.pixels, out)
    assert not np.array_equal(before, out)


def gbuffer_frame(seed=3, width=96, height=64):
    """Colour with a step in its normals and depth: R, G, B, A, N.X, N.Y, N.Z, Z."""
    rng = np.random.default_rng(seed)
    rgba = hdr_frame(seed, width, height)
    n = np.zeros((height, width, 3), np.float32)
    n[..., 2] = 1.0
    n[:, width // 2:] = [0.6, 0.0, 0.8]
    z = np.full((height, width, 1), 2.0, np.float32)
    z[height // 3:] = 3.5 + rng.random((height - height // 3, width, 1), dtype=np.float32) * 0.01
    return np.concatenate([rgba, n, z], axis=2)


CHANNELS = list("RGBA") + ["N.X", "N.Y", "N.Z", "Z"]


@pytest.mark.parametrize("use", ["both", "normal", "depth"])
def test_edge_aa_equals_tool(use, tmp_path):
    src = write_exr(tmp_path / "in.exr", gbuffer_frame(), CHANNELS)
    run_tool("dhdr-aa", src, "--use", use, "--max-offset", "0.75", "-o", tmp_path / "tool.exr")
    mine = dhdr.edge_aa(dhdr.read(str(src)), use=use, max_offset=0.75)
    same_bits(mine.pixels, read_file(tmp_path / "tool.exr"))


def test_edge_aa_with_separate_gbuffer_equals_tool(tmp_path):
    frame = gbuffer_frame()
    colour = write_exr(tmp_path / "in.exr", frame[..., :4], list("RGBA"))
    gbuf = write_exr(tmp_path / "g.exr", frame[..., 4:], CHANNELS[4:])
    run_tool("dhdr-aa", colour, "--gbuffer", gbuf, "-o", tmp_path / "tool.exr")
    expected = read_file(tmp_path / "tool.exr")
    img = dhdr.read(str(colour))
    same_bits(dhdr.edge_aa(img, gbuffer=dhdr.Image(frame[..., 4:], CHANNELS[4:])).pixels,
              expected)
    # Normal and depth as plain arrays.
    same_bits(dhdr.edge_aa(img, normal=frame[..., 4:7], depth=frame[..., 7]).pixels, expected)


def test_edge_aa_missing_geometry_names_the_channel():
    with pytest.raises(ValueError, match="no channel 'N.X'"):
        dhdr.edge_aa(hdr_frame())
    with pytest.raises(ValueError, match="no channel 'Z'"):
        dhdr.edge_aa(hdr_frame(), use="depth")
    with pytest.raises(ValueError, match="normal: expected 3 channel"):
        dhdr.edge_aa(hdr_frame(), normal=np.zeros((64, 96, 2)), use="normal")
    with pytest.raises(ValueError, match="use must be"):
        dhdr.edge_aa(gbuffer_frame(), use="edges")


def motion_frame(seed=5, width=96, height=80):
    """An HDR frame (R, G, B, A) and its G-buffer (Z, motion.X..W): bands at two depths moving
    sideways over a static background."""
    rng = np.random.default_rng(seed)
    colour = np.concatenate([rng.uniform(0.0, 4.0, (height, width, 3)),
                             np.ones((height, width, 1))], axis=-1).astype(np.float32)
    y, x = np.mgrid[0:height, 0:width]
    band = (y // 10) % 2 == 1
    u = np.where(band, 6.0 + (x % 3), 0.0)
    z = np.where(band, 2.0, 20.0)
    g = np.stack([z, -u, np.zeros_like(u), -u, np.zeros_like(u)], axis=-1).astype(np.float32)
    return colour, g


MOTION = ["Z", "motion.X", "motion.Y", "motion.Z", "motion.W"]


def test_motion_blur_equals_tool(tmp_path):
    colour, g = motion_frame()
    src = write_exr(tmp_path / "in.exr", colour, list("RGBA"))
    gbuf = write_exr(tmp_path / "g.exr", g, MOTION)
    run_tool("dhdr-motionblur", src, "--gbuffer", gbuf, "--shutter", "1", "--samples", "9",
             "-o", tmp_path / "tool.exr")
    expected = read_file(tmp_path / "tool.exr")
    img = dhdr.read(str(src))
    same_bits(dhdr.motion_blur(img, gbuffer=dhdr.Image(g, MOTION), shutter=1.0, samples=9).pixels,
              expected)
    # Motion and depth as plain arrays; Blender's channel names.
    same_bits(dhdr.motion_blur(img, motion=g[..., 1:], depth=g[..., 0], shutter=1.0,
                               samples=9).pixels, expected)
    blender = ["ViewLayer.Depth.Z"] + ["ViewLayer.Vector." + c for c in "XYZW"]
    same_bits(dhdr.motion_blur(img, gbuffer=dhdr.Image(g, blender), shutter=1.0,
                               samples=9).pixels, expected)
    assert not np.array_equal(expected, colour)


def test_motion_blur_errors_name_what_is_wrong():
    colour, g = motion_frame()
    with pytest.raises(ValueError, match="no motion channels"):
        dhdr.motion_blur(colour)
    with pytest.raises(ValueError, match="motion: expected 4 channel"):
        dhdr.motion_blur(colour, motion=g[..., 1:3], depth=g[..., 0])
    with pytest.raises(ValueError, match="shutter"):
        dhdr.motion_blur(colour, motion=g[..., 1:], depth=g[..., 0], shutter=3.0)
