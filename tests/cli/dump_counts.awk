# What `apitrace dump --color=never` lists, frame by frame: "frame draws
# triangles" for frames `first` to `last` (awk -v first=A -v last=B).
# Draw calls: glDrawElements, glDrawRangeElements, glDrawArrays and
# glBegin/glEnd; triangles as OpenGL splits each primitive; frames end at
# glXSwapBuffers. Used by capture.sh and capture_nexuiz.sh.
function tris(mode, n) {
  if (mode == "GL_TRIANGLES") return int(n / 3)
  if (mode == "GL_TRIANGLE_STRIP" || mode == "GL_TRIANGLE_FAN" || mode == "GL_POLYGON") return n >= 3 ? n - 2 : 0
  if (mode == "GL_QUADS") return 2 * int(n / 4)
  if (mode == "GL_QUAD_STRIP") return n >= 4 ? 2 * int((n - 2) / 2) : 0
  return -1000000
}
function arg(name,   m) { if (match($0, name " = [A-Z_0-9]+")) { m = substr($0, RSTART, RLENGTH); sub(/.* = /, "", m); return m } return "" }
/ glXSwapBuffers\(/ { if (frame >= first && frame <= last) print frame, draws, triangles; frame++; draws = 0; triangles = 0; next }
/ gl(DrawElements|DrawRangeElements|DrawArrays)\(/ { draws++; triangles += tris(arg("mode"), arg("count")); next }
/ glBegin\(/ { mode = arg("mode"); vertices = 0; next }
/ glVertex[234]/ { vertices++; next }
/ glEnd\(/ { draws++; triangles += tris(mode, vertices); next }
