"""Command line: `dynpaint <command>` (see --help of each command); `python -m dynpaint_addon`
runs the same.

One module per command, each with its `add_parser(sub)`: new, render, bake_shadow, turntable,
animation, demo, make_test_painting, parameters (`params`), make_shape, export_web, farm;
notes.py is how they all say what they guessed. User mistakes (missing files, unreadable images, bad recipes or
options: errors.UserError) end with one line `error: …` on stderr and exit status 1 (2 for
malformed command lines; 130 for Ctrl-C); never a traceback. Before any work an output is
checked (cli/outputs.py: writable, none of the inputs), and every file is written whole.
"""
import argparse
import difflib
import os
import sys

from ..errors import UserError
from . import (animation, bake_shadow, demo, export_web, farm, make_shape, make_test_painting,
               new, parameters, render, turntable)
from .outputs import guard_outputs

COMMANDS = (new, render, turntable, animation, farm, export_web, bake_shadow, make_shape, demo,
            make_test_painting, parameters)


def build_parser():
    ap = argparse.ArgumentParser(
        prog="dynpaint",
        description="Dynamic Painting: relight a painting from its images (pipeline.md). "
                    "Lengths are in image widths; the painting frame has x right, y up, z toward "
                    "the viewer, origin at the painting's centre.")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        command.add_parser(sub)
    return ap


def main(argv=None):
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    unknown = _unknown_command(parser, argv)
    if unknown:
        parser.print_usage(sys.stderr)
        print(f"error: {unknown}", file=sys.stderr)
        return 2
    args = parser.parse_args(argv)
    try:
        guard_outputs(args)         # before any work: --out writable, none of the inputs
        args.func(args)
    except UserError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        # Ctrl-C: outputs are written whole (inputs/whole_files.py), so none is left half done
        print("interrupted: the output being written was left as it was", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # `params | head`: the reader has gone; say nothing more (Python's own advice)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (ValueError, OSError, MemoryError) as exc:
        print(f"error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    return 0


def _unknown_command(parser, argv):
    """'rendr: no such command (did you mean 'render'?)' for a first word that names none."""
    if not argv or argv[0].startswith("-"):
        return ""
    commands = next(a for a in parser._actions
                    if isinstance(a, argparse._SubParsersAction)).choices
    if argv[0] in commands:
        return ""
    close = difflib.get_close_matches(argv[0], list(commands), n=1)
    hint = f" (did you mean '{close[0]}'?)" if close else ""
    return f"'{argv[0]}' is no command{hint}; the commands: {', '.join(commands)}"
