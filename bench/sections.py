"""Sections of a generated document that different benchmarks write: each between
<!-- begin NAME --> and <!-- end NAME --> markers, so that one benchmark rewrites its own part and
keeps the others'."""
import os


def _markers(name):
    return f"<!-- begin {name} -->", f"<!-- end {name} -->"


def replace(path, name, lines):
    """Writes `lines` as section `name` of the file at `path`: in place of the old one, or appended."""
    begin, end = _markers(name)
    text = open(path).read() if os.path.exists(path) else ""
    block = "\n".join([begin, *lines, end])
    if begin in text and end in text:
        text = text[:text.index(begin)] + block + text[text.index(end) + len(end):]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    with open(path, "w") as f:
        f.write(text)


def kept(path, names):
    """The sections `names` of the file at `path` (text to append when rewriting the rest)."""
    if not os.path.exists(path):
        return ""
    text = open(path).read()
    parts = []
    for name in names:
        begin, end = _markers(name)
        if begin in text and end in text:
            parts.append(text[text.index(begin):text.index(end) + len(end)])
    return "\n\n".join(parts)
