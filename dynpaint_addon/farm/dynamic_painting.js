// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco job type "Dynamic Painting turntable" (issue 64): a light orbits a dynamic painting
// once, rendered in chunks of frames by Flamenco's workers — each frame baking its own cos-θ
// shadows on the worker (`dynpaint turntable … --only FIRST-LAST`: a chunk's frames are a whole
// turntable's, bit for bit) — then joined into a video by `frames-to-video` (ffmpeg).
//
// Install: copy this file into the `scripts/` folder beside `flamenco-manager` and restart the
// Manager (`dynpaint farm job-type --install DIR` does it). The program a worker runs is the
// Manager's variable `dynpaint` (two-way variables map it per platform); the recipe and the
// output folder must be on the shared storage (`dynpaint farm submit` copies the recipe there).

const JOB_TYPE = {
    label: "Dynamic Painting turntable",
    description: "A light orbits a dynamic painting once; chunks of frames rendered by the " +
        "workers (each frame bakes its own shadows), then joined into a video",
    settings: [
        { key: "recipe", type: "string", subtype: "file_path", required: true,
          description: "The painting's recipe (painting.toml), an .ora file or a folder of " +
          "layers, on the shared storage as the workers see it" },
        { key: "frames", type: "int32", default: 48, required: true, propargs: {min: 2},
          description: "Frames in one orbit" },
        { key: "chunk_size", type: "int32", default: 4, propargs: {min: 1}, visible: "submission",
          description: "Frames one task renders (each task starts Blender once)" },
        { key: "engine", type: "string", default: "cycles", choices: ["cycles", "eevee"],
          description: "cycles (CPU, any worker) or eevee (needs an OpenGL/EGL driver)" },
        { key: "size", type: "string", default: "",
          description: "Video size 'W H' in pixels (empty: the shape image's size)" },
        { key: "elevation", type: "string", default: "",
          description: "Light elevation in degrees (empty: where the recipe puts the light)" },
        { key: "light", type: "string", default: "",
          description: "The recipe light that orbits (empty: its first Sun)" },
        { key: "clockwise", type: "bool", default: false, description: "Orbit clockwise" },
        { key: "samples", type: "int32", default: 0,
          description: "Render samples per pixel (0: one at the shape image's size)" },
        { key: "fps", type: "int32", default: 24, description: "Frames per second of the video" },
        { key: "render_output_path", type: "string", subtype: "dir_path", required: true,
          description: "Folder on the shared storage for the frames and the video" },
    ]
};

// The turntable's own options as `dynpaint turntable` takes them (its --help).
function turntableArgs(s) {
    const args = ["turntable", s.recipe, "--frames", String(s.frames), "--engine", s.engine,
                  "--fps", String(s.fps)];
    if (s.size) args.push("--size", ...s.size.trim().split(/\s+/));
    if (s.elevation !== "") args.push("--elevation", String(s.elevation));
    if (s.light) args.push("--light", s.light);
    if (s.clockwise) args.push("--clockwise");
    if (s.samples > 0) args.push("--samples", String(s.samples));
    return args;
}

function compileJob(job) {
    const s = job.settings;
    if (!(s.frames >= 2)) throw `frames: at least 2, got ${s.frames}`;
    if (!(s.chunk_size >= 1)) throw `chunk_size: at least 1, got ${s.chunk_size}`;
    const out = s.render_output_path;
    const frames = path.join(out, "frame_######.png");
    const base = turntableArgs(s);
    const renders = [];
    // chunks of consecutive frames, as `--only FIRST-LAST` takes them
    for (let first = 1; first <= s.frames; first += s.chunk_size) {
        const last = Math.min(first + s.chunk_size - 1, s.frames);
        const chunk = first === last ? `${first}` : `${first}-${last}`;
        const task = author.Task(`render-${chunk}`, "misc");
        task.addCommand(author.Command("exec", {
            exe: "{dynpaint}",
            args: base.concat(["--only", chunk, "--out", frames]),
        }));
        renders.push(task);
        job.addTask(task);
    }
    const video = author.Task("video", "ffmpeg");
    video.addCommand(author.Command("frames-to-video", {
        exe: "ffmpeg",
        fps: s.fps,
        inputGlob: path.join(out, "frame_*.png"),
        outputFile: path.join(out, `${path.stem(s.recipe) || "turntable"}.mp4`),
        args: ["-c:v", "h264", "-crf", "18", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
               "-pix_fmt", "yuv420p", "-y"],
    }));
    for (const task of renders) video.addDependency(task);
    job.addTask(video);
}
