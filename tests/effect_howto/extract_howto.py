#!/usr/bin/env python3
"""Builds the effect library docs/effects.md's how-to describes, from the document itself.

    extract_howto.py EFFECTS_MD LIBRARY_HPP OUT_DIR

Takes the how-to's two C++ blocks: the effect's header (the block that starts with "// NAME:")
and the registration (the block with "using EffectLibrary"). Writes OUT_DIR/lptn/effects/NAME.hpp
and OUT_DIR/lptn/effects/library.hpp: the real library.hpp with the registration's includes added
and its list replaced by the document's. The document's list must extend the real one (the how-to
says to append), so a stale document fails the build here, naming the file and line.
"""
import os
import re
import sys


def fail(path, line, why):
    sys.stderr.write(f"{path}:{line}: {why}\n")
    sys.exit(1)


def cpp_blocks(path, text):
    """(first line number, body) of each ```cpp block."""
    blocks, body, start = [], None, 0
    for number, line in enumerate(text.splitlines(), 1):
        if body is None and line.strip() == "```cpp":
            body, start = [], number + 1
        elif body is not None and line.strip() == "```":
            blocks.append((start, "\n".join(body) + "\n"))
            body = None
        elif body is not None:
            body.append(line)
    if body is not None:
        fail(path, start - 1, "unterminated ```cpp block")
    return blocks


def effect_list(text):
    match = re.search(r"using\s+EffectLibrary\s*=\s*EffectList<([^>]*)>\s*;", text)
    return (match, [t.strip() for t in match.group(1).split(",")]) if match else (None, None)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    md_path, library_path, out_dir = sys.argv[1:]
    md = open(md_path, encoding="utf-8").read()
    library = open(library_path, encoding="utf-8").read()

    header = registration = None
    for line, body in cpp_blocks(md_path, md):
        if re.match(r"// [a-z_]+:", body) and "struct" in body:
            header = (line, body)
        elif "using EffectLibrary" in body:
            registration = (line, body)
    if header is None:
        fail(md_path, 1, "no effect header block (a ```cpp block starting with '// name:')")
    if registration is None:
        fail(md_path, 1, "no registration block (a ```cpp block with 'using EffectLibrary')")

    name = re.match(r"// ([a-z_]+):", header[1]).group(1)
    if f'kName = "{name}"' not in header[1]:
        fail(md_path, header[0], f"the header's kName is not \"{name}\"")

    real_match, real = effect_list(library)
    doc_match, doc = effect_list(registration[1])
    if real_match is None:
        fail(library_path, 1, "no 'using EffectLibrary = EffectList<...>;'")
    if doc_match is None:
        fail(md_path, registration[0], "the registration has no complete 'using EffectLibrary = EffectList<...>;'")
    if doc[: len(real)] != real or len(doc) <= len(real):
        fail(md_path, registration[0],
             f"the registration must append to the library's list ({', '.join(real)}), got ({', '.join(doc)})")

    includes = re.findall(r'^#include "[^"]+"$', registration[1], re.M)
    if f'#include "lptn/effects/{name}.hpp"' not in includes:
        fail(md_path, registration[0], f'the registration does not include "lptn/effects/{name}.hpp"')
    last = list(re.finditer(r'^#include "lptn/effects/[^"]+"$', library, re.M))[-1]
    library = library[: last.end()] + "\n" + "\n".join(includes) + library[last.end():]
    library = re.sub(r"using\s+EffectLibrary\s*=\s*EffectList<[^>]*>\s*;", doc_match.group(0), library)

    effects_dir = os.path.join(out_dir, "lptn", "effects")
    os.makedirs(effects_dir, exist_ok=True)
    for file, text in ((f"{name}.hpp", header[1]), ("library.hpp", library)):
        path = os.path.join(effects_dir, file)
        # Rewritten only when changed, so a rebuild after touching the document is as small as it can be.
        if not os.path.exists(path) or open(path, encoding="utf-8").read() != text:
            with open(path + ".tmp", "w", encoding="utf-8") as out:
                out.write(text)
            os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main()
