#!/usr/bin/env python3
"""Object-level SFR written in Python: the C++ scheme `object` (src/oovr/schemes/impl/object.cpp),
call for call, so that oovr's memory system and timing model give it exactly the same numbers.

Paper Section 4.3: objects go to GPMs round-robin, one at a time per GPM; the left and right views
of an object are separate tasks (each a draw of its own, transformed per view, no SMP sharing);
each GPM renders into its own buffer and sends what it drew to the root, GPM 0, which composes the
final frame while it renders its own objects.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/object_level.py [SCENE] [--resolution WxH]

prints the C++ scheme's and this one's results side by side and says whether they are identical.
"""

import argparse
import sys

import oovr


class ObjectLevel(oovr.Scheme):
    name = "object-py"
    description = "object-level SFR in Python: objects round-robin, eyes separate, root composition"

    def run(self, input):
        n = input.gpms
        sim = oovr.FrameSim(input, oovr.sort_last_framebuffers(n))  # the final frame and one buffer per GPM
        composer = oovr.Composer(sim, 0)  # GPM 0, the root, owns every pixel of the final frame
        frame = sim.frame()
        for o, views in enumerate(frame.records_by_object()):
            g = o % n  # round-robin
            for eye, records in enumerate(views):
                sim.command(g)  # each view is a draw of its own: its front-end cost
                geometry = sim.geometry(g, o, 1, frame.triangles_set_up(o, eye))
                if len(records):
                    job = oovr.TileJob(g, records, 0, [geometry])
                    composer.target(job)  # the root's pixels into the final frame, the others' into their own buffer
                    composer.send(job, sim.tiles_together([job])[0])  # then to the root, whose ROPs merge them
                sim.end_draw(g)
        return sim.finish(self.name)


def comparable(result):
    """A result's fields, less the keys of the C++ scheme's own section sort_last: it records its
    composition algorithm (sort_last.composition), which this scheme does not read; it gathers to
    GPM 0, the C++ scheme's default."""
    d = result.to_dict()
    d["config"] = {k: v for k, v in d["config"].items() if not k.startswith("sort_last.")}
    return d


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", nargs="?", default="courtyard")
    ap.add_argument("--resolution", default="1280x1024", help="the whole stereo frame, WxH")
    ap.add_argument("--frames", type=int, default=None, help="frames measured (default: one per GPM)")
    a = ap.parse_args(argv)
    both = oovr.compare(a.scene, ["object", ObjectLevel()], resolution=a.resolution, frames=a.frames)
    print(both)
    cpp, py = both.results
    # Every field of the JSON but the scheme's name is the C++ scheme's.
    a, b = comparable(cpp), comparable(py)
    differ = [k for k in cpp.fields() if k != "scheme" and a[k] != b[k]]
    if differ:
        print("the Python scheme differs from the C++ one in: " + ", ".join(differ))
        return 1
    print(f"identical: every field of the {len(cpp.fields())} in the results, the scheme's name aside")
    return 0


if __name__ == "__main__":
    sys.exit(main())
