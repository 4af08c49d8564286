/* A user BRDF kept in the page's link: {source, values} as JSON, deflated
 * (CompressionStream "deflate-raw") and written in base64url, at most MAX_LINK_CHARS. */

/** Longest encoded BRDF kept in a link: browsers and servers accept URLs of 8 KB and more
 * (2 KB for the oldest); the rest of the page's state needs its share. */
export const MAX_LINK_CHARS = 6000;

const toBase64Url = (bytes) => {
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
};
const fromBase64Url = (text) => {
  const s = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
};

async function pipe(bytes, stream) {
  const out = new Response(new Blob([bytes]).stream().pipeThrough(stream));
  return new Uint8Array(await out.arrayBuffer());
}

export async function encodeLink(source, values) {
  const json = new TextEncoder().encode(JSON.stringify({ s: source, v: values }));
  return toBase64Url(await pipe(json, new CompressionStream("deflate-raw")));
}

/** {source, values}; throws with a sentence when the text is not one of ours. */
export async function decodeLink(text) {
  if (typeof text !== "string" || text.length > MAX_LINK_CHARS) throw new Error(`more than ${MAX_LINK_CHARS} characters`);
  let body;
  try {
    body = JSON.parse(new TextDecoder().decode(await pipe(fromBase64Url(text), new DecompressionStream("deflate-raw"))));
  } catch {
    throw new Error("it is not an encoded .brdf (damaged or cut short?)");
  }
  if (typeof body?.s !== "string") throw new Error("it holds no shader");
  return { source: body.s, values: body.v && typeof body.v === "object" ? body.v : {} };
}
