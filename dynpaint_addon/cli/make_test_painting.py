"""`dynpaint make-test-painting FOLDER`: the built-in test painting as files."""
from ..inputs.testpainting import write_test_painting


def cmd_make_test_painting(args):
    path = write_test_painting(args.folder, args.size)
    print(f"wrote {path}")


def add_parser(sub):
    """Register `make-test-painting` on the command line's subparsers."""
    m = sub.add_parser("make-test-painting", help="write the built-in test painting as files",
                       description="Write the built-in test painting (its images and a "
                       "painting.toml) into FOLDER: a recipe to copy from, or to try every "
                       "command on.")
    m.add_argument("folder", help="folder for painting.toml and its images")
    m.add_argument("--size", type=int, default=256, help="size in pixels (default 256)")
    m.set_defaults(func=cmd_make_test_painting)
