"""Tone-maps a sequence with eye adaptation, as dhdr-tonemap --adapt does: every frame
metered, the metered luminances adapted in frame order, each frame mapped with its adapted
luminance (docs/python.md).

    python3 adapt_sequence.py 'shot.####.exr' FIRST LAST 'out.####.png' [FPS]
"""
import sys

import dhdr


def frame_path(pattern, number):
    width = pattern.count("#")
    return pattern.replace("#" * width, f"{number:0{width}d}")


def main(pattern, first, last, out_pattern, fps=24.0):
    numbers = range(int(first), int(last) + 1)
    frames = [dhdr.read(frame_path(pattern, n)) for n in numbers]
    # Metered as the tool meters: the frames as its reader prepares them.
    stats = dhdr.adapt([dhdr.prepare_frame(f) for f in frames], fps=float(fps))
    for n, frame, s in zip(numbers, frames, stats):
        print(f"frame {n}: metered {dhdr.meter(frame).log_average:.4g}, "
              f"adapted {s.log_average:.4g}")
        dhdr.write(frame_path(out_pattern, n), dhdr.tonemap_frame(frame, stats=s, bits=8))


if __name__ == "__main__":
    main(*sys.argv[1:6])
