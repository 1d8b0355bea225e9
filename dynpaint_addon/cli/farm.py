"""`dynpaint farm`: a turntable rendered by a Flamenco render farm (issue 64; docs/farm.md).

    dynpaint farm submit RECIPE --manager URL [turntable's options] [--chunk-size N]
    dynpaint farm status JOB --manager URL
    dynpaint farm job-type [--install FOLDER]

`submit` copies the recipe and the files it reads onto the farm's shared storage and submits a
job of the type farm/dynamic_painting.js (which the Manager must have: `job-type --install`);
its workers render chunks of frames, each frame baking its own shadows, then join the video.
"""
import os
import shutil

from ..errors import CommandError
from ..farm.flamenco import JOB_TYPE_FILE, job_status, submit
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


def cmd_submit(args):
    check_orbit_options(args)
    if args.chunk_size < 1:
        raise CommandError(f"--chunk-size must be at least 1, got {args.chunk_size}")
    if is_layered_file(args.recipe):
        source = os.path.abspath(args.recipe)
    else:
        source = load_recipe(args.recipe)
        print_notes(source.notes)
    job, output = submit(args.manager, source, job_settings(args), args.name, args.priority)
    tasks = -(-args.frames // args.chunk_size)
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
        print(JOB_TYPE_FILE)
        return
    if not os.path.isdir(args.install):
        raise CommandError(f"--install {args.install}: not a folder (the one holding "
                           f"flamenco-manager)")
    scripts = os.path.join(args.install, "scripts")
    os.makedirs(scripts, exist_ok=True)
    target = shutil.copy(JOB_TYPE_FILE, scripts)
    print(f"farm: installed the job type as {target}: restart the Manager to offer it")


def add_parser(sub):
    """Register `farm` (submit, status, job-type) on the command line's subparsers."""
    farm = sub.add_parser("farm", help="render a turntable on a Flamenco render farm",
                          description="Blender's render farm, Flamenco: its workers render a "
                          "turntable in chunks of frames, each frame baking its own shadows, "
                          "then join them into a video (docs/farm.md).")
    what = farm.add_subparsers(dest="farm_command", required=True, metavar="SUBCOMMAND")
    s = what.add_parser("submit", help="submit a recipe's turntable to a Manager",
                        description="Copy the recipe and the files it reads onto the farm's "
                        "shared storage and submit its turntable.")
    s.add_argument("recipe", help=recipe_help())
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
    jt = what.add_parser("job-type", help="where the Flamenco job type is, or install it",
                         description="Print the path of the job type's file "
                         "(dynamic_painting.js), or copy it into a Manager's scripts/ folder.")
    jt.add_argument("--install", metavar="FOLDER",
                    help="the folder holding flamenco-manager: the job type goes into its "
                    "scripts/ folder")
    jt.set_defaults(func=cmd_job_type)
