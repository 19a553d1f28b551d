// brushwork paint: pen samples to the server over a WebSocket, tiles of the paper back.
"use strict";
const token = new URLSearchParams(location.search).get("token");
const query = token ? "?token=" + encodeURIComponent(token) : "";
const $ = (id) => document.getElementById(id);
const paper = $("paper"), overlay = $("overlay");
const ctx = paper.getContext("2d"), octx = overlay.getContext("2d");
const state = { seq: 0, drawnSeq: -1, tiles: 0, down: false, last: null, heading: 0, flags: [], ws: null,
                painting: null };
window.paint = state;              // for tests and the console
let drawing = Promise.resolve();   // tiles are drawn in the order they come

function send(msg) {
  if (state.ws && state.ws.readyState === WebSocket.OPEN) state.ws.send(JSON.stringify(msg));
}

function status(text) { $("status").textContent = text; }

function loadImage(png) {
  return new Promise((ok, fail) => {
    const img = new Image();
    img.onload = () => ok(img);
    img.onerror = fail;
    img.src = "data:image/png;base64," + png;
  });
}

function drawContact(polys) {
  octx.clearRect(0, 0, overlay.width, overlay.height);
  octx.strokeStyle = "#d33";
  octx.lineWidth = 1;
  for (const p of polys) {
    octx.beginPath();
    for (let i = 0; i < p.length; i += 2) octx.lineTo(p[i], p[i + 1]);
    octx.closePath();
    octx.stroke();
  }
}

const handlers = {
  hello(m) {
    for (const c of [paper, overlay]) { c.width = m.width; c.height = m.height; }
    $("preset").replaceChildren(...m.presets.map((p) => new Option(p, p, false, p === m.settings.preset)));
    $("tufts").replaceChildren(...Array.from({ length: m.max_tufts }, (_, i) =>
      new Option(String(i + 1), String(i + 1), false, i + 1 === m.settings.tufts)));
    state.flags = m.flags;
    $("flags").replaceChildren($("flags").firstElementChild, ...m.flags.map((f) => {
      const label = document.createElement("label");
      label.innerHTML = `<input type="checkbox" id="flag-${f}"> ${f.replace("_map", "")}`;
      label.firstChild.checked = !!m.settings.scene[f];
      label.firstChild.onchange = sendScene;
      return label;
    }));
    state.painting = m.painting;
    links();
    status(`${m.width} x ${m.height} px, ${m.settings.px_per_mm} px/mm`);
  },
  tile(m) {
    drawing = drawing.then(async () => {
      if (m.png) ctx.drawImage(await loadImage(m.png), m.x, m.y);
      drawContact(m.contact);
      state.tiles += 1;
      if (m.seq !== null && m.seq !== undefined) state.drawnSeq = m.seq;
    }).catch((err) => status("a tile could not be drawn: " + err));
  },
  view(m) { $("view").src = "data:image/png;base64," + m.png; },
  error(m) { status("server: " + m.message); console.warn(m.message); },
};

function connect() {
  const ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws" + query);
  ws.onmessage = (e) => { const m = JSON.parse(e.data); if (handlers[m.type]) handlers[m.type](m); };
  ws.onopen = () => { state.ws = ws; };
  ws.onclose = () => { state.ws = null; status("disconnected: reload the page for a new painting (this one's motion log stays in the server's log folder)"); };
}

// one pointer event -> one sample: canvas px, pressure, and the pen's angles
function sample(e) {
  const r = paper.getBoundingClientRect();
  const x = (e.clientX - r.left) * paper.width / r.width, y = (e.clientY - r.top) * paper.height / r.height;
  const s = { x, y, twist: e.twist || 0 };
  const pen = e.pointerType === "pen" || e.pointerType === "touch";
  s.pressure = pen ? e.pressure : Number($("pressure").value);
  if (pen && (e.tiltX || e.tiltY)) {
    s.tiltX = e.tiltX; s.tiltY = e.tiltY;
  } else if (pen && e.altitudeAngle !== undefined && e.altitudeAngle < Math.PI / 2) {
    s.tilt = 90 - e.altitudeAngle * 180 / Math.PI;
    s.azimuth = -e.azimuthAngle * 180 / Math.PI;       // clockwise on the screen -> paper's frame
  } else {
    // a mouse (or an upright pen): the slider's tilt, leaning along the travel
    if (state.last && Math.hypot(x - state.last[0], y - state.last[1]) > 0.5)
      state.heading = Math.atan2(state.last[1] - y, x - state.last[0]) * 180 / Math.PI;
    s.tilt = pen ? 0 : Number($("tilt").value);
    s.azimuth = state.heading;
  }
  state.last = [x, y];
  return s;
}

function sendSamples(events) {
  const samples = events.map(sample);
  for (let i = 0; i < samples.length; i += 256)
    send({ type: "samples", seq: ++state.seq, samples: samples.slice(i, i + 256) });
}

paper.addEventListener("pointerdown", (e) => {
  if (e.button !== 0) return;
  try { paper.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic pointer: nothing to capture */ }
  state.down = true;
  state.last = null;
  sendSamples([e]);
  e.preventDefault();
});
paper.addEventListener("pointermove", (e) => {
  if (!state.down) return;
  const co = e.getCoalescedEvents ? e.getCoalescedEvents() : [];
  sendSamples(co.length ? co : [e]);
});
for (const kind of ["pointerup", "pointercancel"])
  paper.addEventListener(kind, () => {
    if (!state.down) return;
    state.down = false;
    send({ type: "up", seq: ++state.seq });
  });

function sendScene() {
  const scene = {};
  for (const f of state.flags) scene[f] = $("flag-" + f).checked;
  send({ type: "settings", seq: ++state.seq, scene });
}
$("preset").onchange = () => send({ type: "settings", seq: ++state.seq, preset: $("preset").value });
$("tufts").onchange = () => send({ type: "settings", seq: ++state.seq, tufts: Number($("tufts").value) });
$("dip").onclick = () => send({ type: "dip", seq: ++state.seq, ink: Number($("ink").value),
                                wetness: Number($("wetness").value) });
$("undo").onclick = () => send({ type: "undo", seq: ++state.seq });
$("clear").onclick = () => send({ type: "clear", seq: ++state.seq });
document.addEventListener("keydown", (e) => {
  const p = $("pressure");
  if (e.key === "[" || e.key === "]") p.value = Number(p.value) + (e.key === "]" ? 0.05 : -0.05);
  if (e.key === "z" && (e.ctrlKey || e.metaKey)) $("undo").click();
});
// this page's painting (each connection paints its own) and the token, in every link
function links() {
  const q = new URLSearchParams();
  if (state.painting) q.set("painting", state.painting);
  if (token) q.set("token", token);
  const rest = q.toString();
  $("save").href = "image.png" + (rest ? "?" + rest : "");
  $("save-size").href = "image.png?size=" + Number($("size").value) + (rest ? "&" + rest : "");
  $("save-log").href = "log.json" + (rest ? "?" + rest : "");
}
$("size").oninput = links;
links();
connect();
