// SPDX-License-Identifier: GPL-3.0-or-later
//
// Flamenco job type "Dynamic Painting animation" (issue 64): a .blend file's animation as it
// was saved — its scene, camera, frame range and render settings; a turntable made in Blender
// with Add Light Turntable is one — rendered in chunks of frames by Flamenco's workers, each
// frame baking its dynamic paintings' shadows on the worker (`dynpaint animation FILE.blend
// --only FIRST-LAST`), then joined into a video by `frames-to-video` (ffmpeg).
//
// Submitted by `dynpaint farm submit FILE.blend`, or from Blender by Flamenco's own add-on
// (Output Properties › Flamenco), which packs the open file with its images onto the shared
// storage (BAT) and fills in `blendfile`, the frame range and the frame rate. Installed with
// the turntable's (`dynpaint farm job-type --install DIR`); `dynpaint` is the Manager's
// variable naming the program a worker runs. Flamenco loads each job type's file alone, so the
// chunking below is this file's own copy of the turntable's.

const JOB_TYPE = {
    label: "Dynamic Painting animation",
    description: "A .blend file's animation, its dynamic paintings' shadows baked each frame on " +
        "the workers, in chunks of frames, then joined into a video",
    settings: [
        // filled in by Flamenco's add-on with the packed file (a str setting with this key
        // and the file_path subtype), or by `dynpaint farm submit`
        { key: "blendfile", type: "string", subtype: "file_path", required: true,
          visible: "web", description: "The .blend file, on the shared storage" },
        { key: "frames", type: "string", required: true,
          eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
          evalInfo: { showLinkButton: true, description: "Scene frame range" },
          description: "Scene frames to render, FIRST-LAST" },
        { key: "chunk_size", type: "int32", default: 4, propargs: {min: 1}, visible: "submission",
          description: "Frames one task renders (each task starts Blender once)" },
        { key: "fps", type: "float", eval: "C.scene.render.fps / C.scene.render.fps_base",
          visible: "hidden", description: "Frames per second of the video" },
        { key: "render_output_path", type: "string", subtype: "dir_path", required: true,
          visible: "submission",
          description: "Folder on the shared storage for the frames and the video" },
    ]
};

function compileJob(job) {
    const s = job.settings;
    const range = /^\s*(-?\d+)\s*-\s*(-?\d+)\s*$/.exec(s.frames || "");
    if (!range) throw `frames: FIRST-LAST, got '${s.frames}'`;
    const start = parseInt(range[1]), end = parseInt(range[2]);
    if (start < 0 || end < start) throw `frames: ${s.frames}: from frame 0 up`;
    if (!(s.chunk_size >= 1)) throw `chunk_size: at least 1, got ${s.chunk_size}`;
    const out = s.render_output_path;
    const frames = path.join(out, "frame_######.png");
    const renders = [];
    for (let first = start; first <= end; first += s.chunk_size) {
        const last = Math.min(first + s.chunk_size - 1, end);
        const task = author.Task(`render-${first}-${last}`, "misc");
        task.addCommand(author.Command("exec", {
            exe: "{dynpaint}",
            args: ["animation", s.blendfile, "--only", `${first}-${last}`, "--out", frames],
        }));
        renders.push(task);
        job.addTask(task);
    }
    const video = author.Task("video", "ffmpeg");
    video.addCommand(author.Command("frames-to-video", {
        exe: "ffmpeg",
        fps: s.fps || 24,
        inputGlob: path.join(out, "frame_*.png"),
        outputFile: path.join(out, `${path.stem(s.blendfile)}.mp4`),
        args: ["-c:v", "h264", "-crf", "18", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
               "-pix_fmt", "yuv420p", "-y"],
    }));
    for (const task of renders) video.addDependency(task);
    job.addTask(video);
}
