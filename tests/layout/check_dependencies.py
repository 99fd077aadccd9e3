#!/usr/bin/env python3
"""Dependencies point one way (docs/architecture.md, "Layout"): a file may include files of its own
folder and of folders of a lower rank, never of a higher rank or of a sibling of the same rank.
Public headers (include/tumble/) rank with the code that implements them, so that the collision
layer may use the vocabulary (math, shapes, settings) but not the World.

Usage: check_dependencies.py <repository root>. Prints every violation and exits 1 if any."""
import os
import re
import sys

# Folder -> rank. Longest matching prefix wins.
RANKS = {
    "collision": 1,  # math.hpp, aabb.hpp, contact.hpp: the module's vocabulary
    "collision/shapes": 2,
    "collision/broad_phase": 2,
    "collision/sdf": 1.5,  # fields know only the vocabulary; SDF shapes (collision/shapes) use them
    "collision/narrow_phase/gjk_epa": 3,
    "collision/narrow_phase/pairs": 4,
    "collision/narrow_phase": 5,
    "collision/ccd": 6,
    "dynamics": 7,
    "engine": 8,
    "scenes": 9,
    "renders": 9,
    "library": 10,
    "apps": 10,
    "python": 10,
}
# Public headers: the vocabulary every module shares, then the facades of higher modules.
PUBLIC_RANKS = {
    "world.hpp": 8,
    "batch_world.hpp": 8,
    "load_scene.hpp": 9,
    "render.hpp": 9,
    "tumble.hpp": 9,
}
PUBLIC_VOCABULARY_RANK = 0
SOURCE_EXTENSIONS = (".cpp", ".hpp", ".inc")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def folder_of(path):
    """The ranked folder a repository path belongs to, or None (tests, examples, tools)."""
    if path.startswith("include/tumble/"):
        return "include/tumble/" + os.path.basename(path)
    best = None
    for folder in RANKS:
        if path == folder or path.startswith(folder + "/"):
            if best is None or len(folder) > len(best):
                best = folder
    return best


def rank_of(folder):
    if folder.startswith("include/tumble/"):
        return PUBLIC_RANKS.get(os.path.basename(folder), PUBLIC_VOCABULARY_RANK)
    return RANKS[folder]


def resolve(root, including, name):
    """The repository path an include names: from the root, from include/, or beside the file."""
    for candidate in (name, "include/" + name, os.path.join(os.path.dirname(including), name)):
        if os.path.isfile(os.path.join(root, candidate)):
            return os.path.normpath(candidate)
    return None


def violations(root):
    found = []
    tops = [f for f in RANKS if "/" not in f] + ["include/tumble"]
    for top in tops:
        base = os.path.join(root, top)
        if not os.path.isdir(base):
            continue
        for directory, _, files in os.walk(base):
            for f in files:
                if not f.endswith(SOURCE_EXTENSIONS):
                    continue
                path = os.path.relpath(os.path.join(directory, f), root)
                source = folder_of(path)
                if source is None:
                    continue
                text = open(os.path.join(root, path), encoding="utf-8").read()
                for name in INCLUDE.findall(text):
                    target_path = resolve(root, path, name)
                    if target_path is None:
                        continue  # a system or generated header
                    target = folder_of(target_path)
                    if target is None:
                        found.append(f"{path} includes {name}, which is outside the modules")
                        continue
                    if source.startswith("include/tumble/") and not target.startswith(
                        "include/tumble/"
                    ):
                        found.append(f"{path} (public) includes the internal {name}")
                        continue
                    same_folder = os.path.dirname(path) == os.path.dirname(target_path)
                    if same_folder or source == target:
                        continue
                    if rank_of(target) >= rank_of(source) and not target.startswith(
                        "include/tumble/"
                    ):
                        found.append(
                            f"{path} (rank {rank_of(source)}) includes {name} "
                            f"(rank {rank_of(target)})"
                        )
                    elif target.startswith("include/tumble/") and rank_of(target) > rank_of(source):
                        found.append(
                            f"{path} (rank {rank_of(source)}) includes the public {name} "
                            f"(rank {rank_of(target)})"
                        )
    return found


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    found = violations(root)
    for v in found:
        print(v)
    print(f"{len(found)} include(s) against the direction of the dependencies")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
