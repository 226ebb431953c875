"""The tone-map stage from Python against dhdr-tonemap on the same files, bit for bit."""
import numpy as np
import pytest

import dhdr
from conftest import hdr_frame, range_error_is_the_tools, read_file, run_tool, tool_error, write_exr

OPERATORS = ["reinhard", "reinhard-local", "drago", "hable", "pbr-neutral", "agx", "exposure",
             "aces", "none"]


def same_bits(a, b):
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    assert a.shape == b.shape and a.dtype == b.dtype
    assert np.array_equal(a.view(np.uint8), b.view(np.uint8)), \
        f"{np.count_nonzero(a != b)} of {a.size} values differ"


@pytest.mark.parametrize("op", OPERATORS)
def test_operator_exr_equals_tool(op, frame_exr, tmp_path):
    run_tool("dhdr-tonemap", frame_exr, "--op", op, "--exposure", "0.5", "-o", tmp_path / "tool.exr")
    mine = dhdr.tonemap_frame(dhdr.read(str(frame_exr)), op=op, exposure=0.5)
    dhdr.write(str(tmp_path / "py.exr"), mine)  # half, through the tools' writer
    same_bits(read_file(tmp_path / "py.exr"), read_file(tmp_path / "tool.exr"))


@pytest.mark.parametrize("bits", [8, 16])
def test_png_equals_tool(bits, frame_exr, tmp_path):
    run_tool("dhdr-tonemap", frame_exr, "--bits", bits, "-o", tmp_path / "tool.png")
    mine = dhdr.tonemap_frame(dhdr.read(str(frame_exr)), bits=bits)
    assert mine.dtype == (np.uint8 if bits == 8 else np.uint16)
    same_bits(mine, read_file(tmp_path / "tool.png"))


def test_metering_options_equal_tool(frame_exr, tmp_path):
    args = ["--metering", "histogram", "--percentiles", "10,90", "--weights", "rec709",
            "--delta", "0.001", "--white", "2.5", "--key", "0.25", "--view", "ACES"]
    run_tool("dhdr-tonemap", frame_exr, *args, "-o", tmp_path / "tool.exr")
    mine = dhdr.tonemap_frame(dhdr.read(str(frame_exr)), metering="histogram",
                              percentiles=(10, 90), weights="rec709", delta=0.001, white=2.5,
                              key=0.25, view="ACES")
    dhdr.write(str(tmp_path / "py.exr"), mine)
    same_bits(read_file(tmp_path / "py.exr"), read_file(tmp_path / "tool.exr"))


def test_adaptation_over_frames_equals_tool(tmp_path):
    # Three frames whose brightness jumps: the adapted luminance lags behind.
    for i, scale in enumerate([1.0, 8.0, 8.0], start=1):
        write_exr(tmp_path / f"shot.{i:04d}.exr", hdr_frame(seed=i) * [scale, scale, scale, 1],
                  list("RGBA"))
    run_tool("dhdr-tonemap", tmp_path / "shot.####.exr", "--adapt", "--fps", "12",
             "-o", tmp_path / "tool.####.exr")
    frames = [dhdr.read(str(tmp_path / f"shot.{i:04d}.exr")) for i in (1, 2, 3)]
    stats = dhdr.adapt(frames, fps=12)
    metered = [dhdr.meter(f).log_average for f in frames]
    assert stats[0].log_average == metered[0] and stats[2].log_average < metered[2]
    assert [s.log_average for s in stats] == dhdr.adapt_luminance(metered, fps=12)
    for i, (frame, s) in enumerate(zip(frames, stats), start=1):
        dhdr.write(str(tmp_path / "py.exr"), dhdr.tonemap_frame(frame, stats=s))
        same_bits(read_file(tmp_path / "py.exr"), read_file(tmp_path / f"tool.{i:04d}.exr"))


def test_errors_carry_the_tools_message(frame_exr, tmp_path):
    bad = run_tool("dhdr-tonemap", frame_exr, "--view", "Nope", "-o", tmp_path / "x.png",
                   check=False)
    with pytest.raises(ValueError) as e:
        dhdr.to_display(dhdr.read(str(frame_exr)), view="Nope")
    assert str(e.value) == tool_error(bad)
    missing = tmp_path / "missing.exr"
    bad = run_tool("dhdr-tonemap", missing, "-o", tmp_path / "x.png", check=False)
    with pytest.raises(RuntimeError) as e:
        dhdr.read(str(missing))
    assert str(e.value) == tool_error(bad)


@pytest.mark.parametrize("kwargs, word", [
    (dict(op="filmic"), "op must be"), (dict(key=0), "key: 0 is outside"),
    (dict(white=-1), "white"), (dict(metering="spot"), "metering"),
    (dict(percentiles=(90, 10)), "percentiles"), (dict(weights="p3"), "weights"),
    (dict(exposure=float("nan")), "exposure")])
def test_bad_parameters_raise_value_error(kwargs, word):
    with pytest.raises(ValueError, match=word):
        dhdr.tone_map(hdr_frame(), **kwargs)


@pytest.mark.parametrize("keyword, value", [
    ("key", 0), ("exposure", 65), ("phi", 0), ("epsilon", 1.5), ("drago_bias", 0),
    ("delta", 0)])
def test_range_errors_are_the_tools(keyword, value, tmp_path):
    option = "--" + keyword.replace("_", "-")
    args = ["in.exr", "-o", tmp_path / "x.png"]
    range_error_is_the_tools(lambda: dhdr.tone_map(hdr_frame(), **{keyword: value}),
                             "dhdr-tonemap", option, value, *args)
    if keyword == "delta":
        range_error_is_the_tools(lambda: dhdr.meter(hdr_frame(), delta=value), "dhdr-tonemap",
                                 option, value, *args)


@pytest.mark.parametrize("white", [-1, 0, float("nan"), "bright", "1e999"])
def test_white_errors_are_the_tools(white, frame_exr, tmp_path):
    # One rule (libtonemap's parseWhite) in both spellings: the number as Python writes it.
    bad = run_tool("dhdr-tonemap", frame_exr, "--white", str(white), "-o", tmp_path / "x.png",
                   check=False)
    assert bad.returncode == 2
    assert "usage error: --white must be a positive number, auto or inf" in bad.stderr
    shown = white if isinstance(white, str) else repr(float(white))
    with pytest.raises(ValueError) as e:
        dhdr.tone_map(hdr_frame(), white=white)
    assert str(e.value) == ("white must be a positive number, 'auto' or 'inf', got '%s'" % shown)


def test_adaptation_fps_range_is_the_tools(tmp_path):
    args = ["in.####.exr", "--adapt", "-o", tmp_path / "x.####.png"]
    range_error_is_the_tools(lambda: dhdr.adapt([hdr_frame()], fps=0), "dhdr-tonemap", "--fps",
                             0, *args)
    range_error_is_the_tools(lambda: dhdr.adapt_luminance([0.2, 0.3], fps=1001), "dhdr-tonemap",
                             "--fps", 1001, *args)
    range_error_is_the_tools(lambda: dhdr.adapt_luminance([0.2, 0.3], rate=1.5), "dhdr-tonemap",
                             "--adapt-rate", 1.5, *args, keyword="rate")
    range_error_is_the_tools(lambda: dhdr.adapt([hdr_frame()], speed=0), "dhdr-tonemap",
                             "--adapt-speed", 0, *args, keyword="speed")


def test_adaptation_rate_and_speed_follow_the_seeds_formula():
    # adapted += (L - adapted)(1 - rate^(speed/fps)): one step from 1 towards 2.
    out = dhdr.adapt_luminance([1.0, 2.0], fps=10, rate=0.5, speed=20)
    assert out[0] == 1.0
    assert abs(out[1] - (1.0 + (1.0 - 0.5 ** 2.0))) < 1e-12
    assert dhdr.adapt_luminance([1.0, 2.0], rate=1.0) == [1.0, 1.0]


@pytest.mark.parametrize("op, extra", [("reinhard-local", ["--phi", "4", "--epsilon", "0.1"]),
                                       ("drago", ["--drago-bias", "0.7"])])
def test_operator_parameters_equal_tool(op, extra, frame_exr, tmp_path):
    run_tool("dhdr-tonemap", frame_exr, "--op", op, *extra, "-o", tmp_path / "tool.exr")
    keywords = {extra[i][2:].replace("-", "_"): float(extra[i + 1]) for i in range(0, len(extra), 2)}
    mine = dhdr.tonemap_frame(dhdr.read(str(frame_exr)), op=op, **keywords)
    dhdr.write(str(tmp_path / "py.exr"), mine)
    same_bits(read_file(tmp_path / "py.exr"), read_file(tmp_path / "tool.exr"))
    default = dhdr.tonemap_frame(dhdr.read(str(frame_exr)), op=op)
    assert not np.array_equal(default.pixels, mine.pixels)


def test_meter_histogram_and_stats_object():
    img = hdr_frame()
    s = dhdr.meter(img, metering="histogram")
    assert s.pixels == 96 * 64 - 16  # alpha-0 pixels are left out
    assert s.transparent_pixels == 16
    given = dhdr.LuminanceStats(log_average=s.log_average, max_luminance=s.max_luminance)
    a = dhdr.tone_map(img, metering="histogram").pixels
    b = dhdr.tone_map(img, stats=dhdr.meter(img, metering="histogram")).pixels
    same_bits(a, b)
    # L / (1 + L) with no white point: display luminance below 1 (colour may pass it).
    out = dhdr.tone_map(img, stats=given, white="inf").pixels
    assert (out[..., :3] @ np.array([0.27, 0.67, 0.06], np.float32)).max() < 1.0


def test_quantize_forms():
    d = dhdr.to_display(dhdr.tone_map(hdr_frame()))
    q = dhdr.quantize(d, dither=False)
    assert q.dtype == np.uint8 and q.shape == (64, 96, 4)
    expect = np.floor(np.clip(d.pixels, 0, 1) * 255 + 0.5).astype(np.uint8)
    same_bits(q, expect)
    dst = np.zeros((64, 96, 4), np.uint16)
    assert dhdr.quantize(dst, d, dither=False)
    assert dst.max() > 255
    with pytest.raises(ValueError, match="bits"):
        dhdr.quantize(d, bits=12)
    with pytest.raises(TypeError, match="uint8 or uint16"):
        dhdr.quantize(np.zeros((64, 96, 4), np.int32), d)


def test_replace_non_finite_counts():
    img = dhdr.Image(np.array([[[np.nan, np.inf, -np.inf], [-1.0, 0.5, 2.0]]], np.float32))
    counts = dhdr.replace_non_finite(img, zero_negative=True)
    assert counts == dict(nan=1, positive_inf=1, negative_inf=1, negative=1)
    assert img.pixels.tolist() == [[[0.0, 65504.0, 0.0], [0.0, 0.5, 2.0]]]


def test_describe_display_is_what_the_tool_says(frame_exr, tmp_path):
    out = run_tool("dhdr-tonemap", frame_exr, "--view", "ACES", "-v", "-o", tmp_path / "x.png")
    said = [l for l in out.stderr.splitlines() if ": display " in l][0].split(": display ", 1)[1]
    description, colorspace = dhdr.describe_display(view="ACES")
    assert description == said
    assert colorspace == "sRGB"  # PNG gets its sRGB chunk
