"""`dynpaint farm`: a turntable or a .blend's animation rendered by a Flamenco render farm
(issue 64; docs/farm.md).

    dynpaint farm submit RECIPE|FILE.blend --manager URL [turntable's options] [--chunk-size N]
    dynpaint farm status JOB --manager URL
    dynpaint farm job-type [--install FOLDER]

`submit` copies the recipe and the files it reads (or the .blend packed with its images) onto
the farm's shared storage and submits a job of the types in farm/ (which the Manager must have:
`job-type --install`); its workers render chunks of frames, each frame baking its own shadows,
then join the video.
"""
import argparse
import os
import shutil

from ..errors import CommandError
from ..farm.blend_files import is_blend, scene_frames
from ..farm.flamenco import JOB_TYPE_FILES, job_status, submit
from ..inputs.layered_files import is_layered_file
from ..inputs.recipe import load_recipe
from ..inputs.samples import recipe_help
from .notes import print_notes
from .turntable import add_orbit_options, check_orbit_options


def job_settings(args):
    """The job type's settings (dynamic_painting.js) of `turntable`'s orbit options."""
    return {"frames": args.frames, "chunk_size": args.chunk_size, "engine": args.engine,
            "size": "" if args.size is None else f"{args.size[0]} {args.size[1]}",
            "elevation": "" if args.elevation is None else f"{args.elevation:g}",
            "light": args.light or "", "clockwise": bool(args.clockwise),
            "samples": args.samples or 0, "fps": args.fps}


def orbit_options_given(args):
    """The turntable's options (add_orbit_options) given other than their defaults."""
    orbit = argparse.ArgumentParser(add_help=False)
    add_orbit_options(orbit)
    defaults = vars(orbit.parse_args([]))
    return [f"--{key.replace('_', '-')}" for key, value in defaults.items()
            if getattr(args, key) != value]


def blend_settings(args):
    """The animation job type's settings (dynamic_painting_animation.js) of a .blend: its
    scene's frame range and rate → (settings, frames)."""
    given = orbit_options_given(args)
    if given:
        raise CommandError(f"{args.recipe}: a .blend renders its own animation (its frame "
                           f"range, camera and render settings, as saved): {', '.join(given)} "
                           f"are a recipe's turntable's options")
    first, last, fps = scene_frames(args.recipe)
    return {"frames": f"{first}-{last}", "chunk_size": args.chunk_size, "fps": fps}, \
        last - first + 1


def cmd_submit(args):
    if args.chunk_size < 1:
        raise CommandError(f"--chunk-size must be at least 1, got {args.chunk_size}")
    if is_blend(args.recipe):
        if not os.path.isfile(args.recipe):
            raise CommandError(f"{args.recipe}: no such file")
        settings, frames = blend_settings(args)
        source = os.path.abspath(args.recipe)
    else:
        check_orbit_options(args)
        settings, frames = job_settings(args), args.frames
        if is_layered_file(args.recipe):
            source = os.path.abspath(args.recipe)
        else:
            source = load_recipe(args.recipe)
            print_notes(source.notes)
    job, output = submit(args.manager, source, settings, args.name, args.priority)
    tasks = -(-frames // args.chunk_size)
    print(f"farm: submitted '{job['name']}' ({tasks} render tasks of up to {args.chunk_size} "
          f"frames, then the video): job {job['id']}, status {job['status']}")
    print(f"farm: its frames and video go to {output}")
    print(f"farm: `dynpaint farm status {job['id']} --manager {args.manager}` says how far "
          f"it is")


def cmd_status(args):
    job, counts = job_status(args.manager, args.job)
    tasks = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    print(f"farm: '{job['name']}' is {job['status']} ({tasks or 'no tasks'})"
          + (f": {job['activity']}" if job.get("activity") else ""))


def cmd_job_type(args):
    if args.install is None:
        print("\n".join(JOB_TYPE_FILES))
        return
    if not os.path.isdir(args.install):
        raise CommandError(f"--install {args.install}: not a folder (the one holding "
                           f"flamenco-manager)")
    scripts = os.path.join(args.install, "scripts")
    os.makedirs(scripts, exist_ok=True)
    for file in JOB_TYPE_FILES:
        target = shutil.copy(file, scripts)
        print(f"farm: installed the job type {target}")
    print("farm: restart the Manager to offer them")


def add_parser(sub):
    """Register `farm` (submit, status, job-type) on the command line's subparsers."""
    farm = sub.add_parser("farm", help="render a turntable on a Flamenco render farm",
                          description="Blender's render farm, Flamenco: its workers render a "
                          "turntable in chunks of frames, each frame baking its own shadows, "
                          "then join them into a video (docs/farm.md).")
    what = farm.add_subparsers(dest="farm_command", required=True, metavar="SUBCOMMAND")
    s = what.add_parser("submit", help="submit a recipe's turntable, or a .blend's "
                        "animation, to a Manager",
                        description="Copy the recipe and the files it reads onto the farm's "
                        "shared storage and submit its turntable; or a .blend file, packed "
                        "with the files it uses, and submit its animation as saved (its frame "
                        "range, camera and render settings; a turntable made in Blender is "
                        "one).")
    s.add_argument("recipe", metavar="RECIPE|FILE.blend",
                   help=recipe_help() + "; or a .blend file")
    s.add_argument("--manager", required=True, metavar="URL",
                   help="the Flamenco Manager's address, e.g. http://farm:8080/")
    add_orbit_options(s)
    s.add_argument("--chunk-size", type=int, default=4,
                   help="frames one task renders (each task starts Blender once; default 4)")
    s.add_argument("--name", help="the job's name (default: the painting's and the time)")
    s.add_argument("--priority", type=int, default=50, help="the job's priority (default 50)")
    s.set_defaults(func=cmd_submit)
    st = what.add_parser("status", help="say how far a submitted job is")
    st.add_argument("job", help="the job's id (submit prints it)")
    st.add_argument("--manager", required=True, metavar="URL", help="the Manager's address")
    st.set_defaults(func=cmd_status)
    jt = what.add_parser("job-type", help="where the Flamenco job types are, or install them",
                         description="Print the paths of the job types' files (a recipe's "
                         "turntable, a .blend's animation), or copy them into a Manager's "
                         "scripts/ folder.")
    jt.add_argument("--install", metavar="FOLDER",
                    help="the folder holding flamenco-manager: the job types go into its "
                    "scripts/ folder")
    jt.set_defaults(func=cmd_job_type)
