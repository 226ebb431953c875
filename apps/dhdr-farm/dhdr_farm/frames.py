"""Frame patterns as the dhdr tools read them (apps/common/frames.cpp) and frame chunks."""

import os
import re

_PRINTF = re.compile(r"%(0?([0-9]*))d")
# The widest pattern the tools take (apps/common/frames.h, kMaxFrameWidth): frame numbers
# have at most 9 digits and a sign; a wider pattern is a typo.
MAX_WIDTH = 16


class FramePattern:
    """`shot.####.exr` (the last run of # in the file name) or `shot.%04d.exr`."""

    def __init__(self, text):
        self.text = text
        name = text.rfind("/") + 1
        end = text.rfind("#")
        self.width = -1
        if end >= name and end != -1:
            begin = end
            while begin > name and text[begin - 1] == "#":
                begin -= 1
            self.prefix, self.suffix, self.width = text[:begin], text[end + 1:], end - begin + 1
            return
        m = _PRINTF.search(text[name:])
        if m:
            self.prefix = text[: name + m.start()]
            self.suffix = text[name + m.end():]
            self.width = int(m.group(2)) if m.group(2) else 0

    @property
    def is_sequence(self):
        return self.width >= 0

    def path(self, frame):
        if not self.is_sequence:
            return self.text
        digits = "%0*d" % (self.width, frame)
        return self.prefix + digits + self.suffix


def parse_range(text):
    """'A-B' or 'A' (A and B may be negative: '-5--1') -> (A, B); ValueError when malformed."""
    m = re.fullmatch(r"\s*(-?\d+)\s*(?:-\s*(-?\d+)\s*)?", text)
    if not m:
        raise ValueError("frames must be A-B or A (e.g. 1-240), not %r" % text)
    first = int(m.group(1))
    last = int(m.group(2)) if m.group(2) is not None else first
    if last < first:
        raise ValueError("frames %s: the last frame is before the first" % text)
    if first < -99999999 or last > 999999999 or last - first + 1 > 1000000:
        raise ValueError("frames %s: frames must lie in [-99999999, 999999999], at most "
                         "1000000 of them (the tools' limits)" % text)
    return first, last


def chunks(first, last, size):
    """[(first, last), ...] of at most `size` frames each, in order; chunk i is task i."""
    if size < 1:
        raise ValueError("--chunk must be at least 1")
    return [(a, min(a + size - 1, last)) for a in range(first, last + 1, size)]


def exists_complete(path):
    """Whether `path` is there: the tools write to a temporary name and rename, so a file
    under its final name is complete."""
    return os.path.isfile(path)
