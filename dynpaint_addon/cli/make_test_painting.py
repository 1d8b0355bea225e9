"""`dynpaint make-test-painting FOLDER`: the built-in test painting as files — never over a
painting's own files without --force (issue 60)."""
import os

from ..errors import CommandError
from ..inputs.testpainting import builtin_painting_files, write_test_painting


def cmd_make_test_painting(args):
    there = [name for name in builtin_painting_files()
             if os.path.exists(os.path.join(args.folder, name))]
    if there and not args.force:
        raise CommandError(f"{args.folder} holds {', '.join(there)} already: writing the test "
                           f"painting would replace them; choose another folder, or pass "
                           f"--force to replace them")
    path = write_test_painting(args.folder, args.size)
    if there:
        print(f"replaced {', '.join(there)} (--force)")
    print(f"wrote {path}")


def add_parser(sub):
    """Register `make-test-painting` on the command line's subparsers."""
    m = sub.add_parser("make-test-painting", help="write the built-in test painting as files",
                       description="Write the built-in test painting (its images and a "
                       "painting.toml) into FOLDER: a recipe to copy from, or to try every "
                       "command on.")
    m.add_argument("folder", help="folder for painting.toml and its images")
    m.add_argument("--size", type=int, default=256, help="size in pixels (default 256)")
    m.add_argument("--force", action="store_true",
                   help="write over the files of a painting already in FOLDER")
    m.set_defaults(func=cmd_make_test_painting)
