"""The one reader of TUM RGB-D text files: rgb.txt / depth.txt (stamp filename), groundtruth.txt
and trajectories (stamp tx ty tz qx qy qz qw), and the project's own id/stamp/pose text files.

Every reader skips blank lines and '#' comments and raises InputError naming the file and line.
Stamps are kept exactly as (secs, nsecs) where it matters (bags); stamp_seconds() gives floats.
ATE and trajectory alignment are evo's (scripts/bench/ate.py), not this module's.
"""
import math
import re


class InputError(Exception):
    """Bad input: the message names the file (and line)."""


def parse_stamp(text):
    """'1305031229.528748' -> (secs, nsecs) exactly, without float rounding."""
    m = re.fullmatch(r'(\d+)(?:\.(\d{0,9})\d*)?', text)
    if m:
        return int(m.group(1)), int((m.group(2) or '').ljust(9, '0'))
    value = float(text)  # exotic but valid forms such as 1.3e9; ValueError if not a number
    if not math.isfinite(value) or value < 0:
        raise ValueError(text)
    secs = int(value)
    return secs, int(round((value - secs) * 1e9))


def stamp_seconds(stamp):
    """(secs, nsecs) -> float seconds."""
    return stamp[0] + stamp[1] * 1e-9


def data_lines(path):
    """Yields (line number, text, words) for each non-comment, non-blank line."""
    try:
        with open(path, 'r') as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise InputError('%s: cannot read (%s)' % (path, e.strerror or e))
    except UnicodeDecodeError:
        raise InputError('%s: not a text file' % path)
    for number, text in enumerate(lines, 1):
        stripped = text.strip()
        if stripped and not stripped.startswith('#'):
            yield number, text, stripped.split()


def read_list(path):
    """rgb.txt / depth.txt -> [(stamp, path relative to the folder, line number)]."""
    entries = []
    for number, text, words in data_lines(path):
        try:
            if len(words) != 2:
                raise ValueError
            entries.append((parse_stamp(words[0]), words[1], number))
        except ValueError:
            raise InputError("%s:%d: malformed line (expected 'timestamp filename'): '%s'" % (path, number, text))
    return entries


def read_poses(path, normalize=True):
    """groundtruth.txt or a TUM trajectory -> [(stamp, [tx ty tz qx qy qz qw], line number)],
    quaternions normalised (refused when of zero length)."""
    poses = []
    for number, text, words in data_lines(path):
        try:
            if len(words) != 8:
                raise ValueError
            values = [float(w) for w in words[1:]]
            if not all(math.isfinite(v) for v in values):
                raise ValueError
            norm = math.sqrt(sum(v * v for v in values[3:]))
            if norm < 1e-6:
                raise ValueError
            if normalize:
                values[3:] = [v / norm for v in values[3:]]
            poses.append((parse_stamp(words[0]), values, number))
        except ValueError:
            raise InputError("%s:%d: malformed line (expected 'timestamp tx ty tz qx qy qz qw'): '%s'"
                             % (path, number, text))
    return poses


def list_seconds(path):
    """The stamps of rgb.txt / depth.txt as float seconds, in file order."""
    return [stamp_seconds(s) for s, _, _ in read_list(path)]


def pose_seconds(path):
    """The stamps of a TUM trajectory as float seconds, in file order."""
    return [stamp_seconds(s) for s, _, _ in read_poses(path)]


def read_records(path, tag_lengths):
    """The project's own text records (one record a line, the first word a tag or a number):
    tag_lengths maps the first word (or None for any) to the number of words a line must have.
    Returns [(line number, words)]."""
    out = []
    for number, text, words in data_lines(path):
        expected = tag_lengths.get(words[0], tag_lengths.get(None))
        if expected is None or len(words) != expected:
            raise InputError('%s:%d: malformed line: %s' % (path, number, text))
        out.append((number, words))
    return out
