/* Desktop GLSL, as `.brdf` files write it, made GLSL ES 3.00 (WebGL2) without the user
 * editing it — line for line, so that compile errors keep the file's line numbers:
 *
 * - integer literals where a float is meant (`pow(x, 2)`, `1 - x`, `4 * PI`): desktop
 *   GLSL converts int to float implicitly, ES does not. Each decimal integer literal
 *   becomes a float literal (`2` → `2.0`) except where an int is meant: inside `[ ]`, in
 *   a statement declaring an int (`int n = 4;`), in a `for (int …)` header, and in a
 *   `#define` whose name is used in one of those places. (Not covered: an int variable
 *   compared with a literal outside those places; a literal `1/2`, which desktop GLSL
 *   computes as integer 0, becomes 0.5.)
 * - a shader's own definition of a built-in function's name (`vec3 reflect(vec3 I, vec3 N)`,
 *   `float smoothstep(float a, float b, float x)`: Disney's Phong and anisotropic files):
 *   desktop GLSL (the explorer compiles `#version 410`) lets a shader redefine a built-in,
 *   GLSL ES 3.00 forbids redefining or overloading one, so that name becomes NAME_user
 *   everywhere in the shader. (Not covered: a call to another of the built-in's overloads
 *   under that name, say smoothstep of vec3s beside a float one of the file's own.)
 * - `#version` and `#extension` lines blanked (the page writes its own `#version 300 es`);
 * - precision: the page's head declares highp;
 * - parameters as uniforms (float, bool, vec3), all on one line before the shader.
 */

const INT_TYPES = new Set(["int", "uint", "ivec2", "ivec3", "ivec4", "uvec2", "uvec3", "uvec4"]);
const TOKEN = /\/\/[^\n]*|\/\*[\s\S]*?\*\/|[A-Za-z_]\w*|\d+\.\d*(?:[eE][+-]?\d+)?[fF]?|\.\d+(?:[eE][+-]?\d+)?[fF]?|\d+[eE][+-]?\d+[fF]?|0[xX][0-9a-fA-F]+[uU]?|\d+[uU]?|\s+|[\s\S]/g;
const INT_LITERAL = /^\d+$/;

/** Names used where an int is meant: in `[ ]` and in `for (int …)` headers. */
function intNames(src) {
  const out = new Set();
  const take = (text) => { for (const m of text.matchAll(/[A-Za-z_]\w*/g)) out.add(m[0]); };
  for (const m of src.matchAll(/\[([^\]]*)\]/g)) take(m[1]);
  for (const m of src.matchAll(/\bfor\s*\(\s*(?:int|uint)\b([^)]*)\)/g)) take(m[1]);
  return out;
}

/** The source with float literals where desktop GLSL would convert ints. */
export function floatLiterals(src) {
  const keepDefines = intNames(src);
  let out = "";
  let stmtStart = true, intStmt = false, bracket = 0, forParen = 0, intFor = false, parenDepth = 0;
  let afterFor = false, defineName = null, inDefine = false, defineKeep = false, inDirective = false;
  for (const m of src.matchAll(TOKEN)) {
    let t = m[0];
    if (t.startsWith("//") || t.startsWith("/*")) { out += t; continue; }
    if (/^\s+$/.test(t)) {
      if (t.includes("\n")) {
        if (inDirective) stmtStart = true;           // a directive line ends like a statement
        inDefine = defineKeep = inDirective = false;
      }
      out += t;
      continue;
    }
    if (t === "#") {
      // a preprocessor line: `#define NAME value` keeps ints if NAME is used as an int
      const rest = src.slice(m.index + 1).match(/^\s*define\s+([A-Za-z_]\w*)/);
      inDefine = !!rest;
      inDirective = true;
      defineName = rest ? rest[1] : null;
      defineKeep = !!rest && keepDefines.has(defineName);
      out += t;
      continue;
    }
    if (INT_LITERAL.test(t)) {
      const keep = bracket > 0 || intStmt || intFor || defineKeep;
      out += keep ? t : `${t}.0`;
      stmtStart = false;
      continue;
    }
    if (t === "[") bracket++;
    else if (t === "]") bracket = Math.max(0, bracket - 1);
    else if (t === "(") {
      parenDepth++;
      if (afterFor) { forParen = parenDepth; afterFor = false; intFor = false; stmtStart = true; out += t; continue; }
    } else if (t === ")") {
      if (forParen && parenDepth === forParen) { forParen = 0; intFor = false; stmtStart = true; }
      parenDepth = Math.max(0, parenDepth - 1);
    } else if (t === ";" || t === "{" || t === "}") {
      if (!forParen) { stmtStart = true; intStmt = false; out += t; continue; }
    }
    if (/^[A-Za-z_]/.test(t)) {
      if (t === "for") afterFor = true;
      if (stmtStart && !inDefine) {
        if (forParen) intFor = INT_TYPES.has(t);
        else intStmt = INT_TYPES.has(t) || (t === "const" && INT_TYPES.has(nextWord(src, m.index + t.length)));
      }
    }
    stmtStart = false;
    out += t;
  }
  return out;
}

function nextWord(src, from) {
  const m = src.slice(from).match(/^\s*([A-Za-z_]\w*)/);
  return m ? m[1] : "";
}

/** GLSL ES 3.00's built-in functions (its §8), which a shader may not redefine. */
const BUILTINS = new Set(("radians degrees sin cos tan asin acos atan sinh cosh tanh asinh acosh atanh pow exp log "
  + "exp2 log2 sqrt inversesqrt abs sign floor trunc round roundEven ceil fract mod modf min max clamp mix step "
  + "smoothstep isnan isinf floatBitsToInt floatBitsToUint intBitsToFloat uintBitsToFloat packSnorm2x16 "
  + "unpackSnorm2x16 packUnorm2x16 unpackUnorm2x16 packHalf2x16 unpackHalf2x16 length distance dot cross "
  + "normalize faceforward reflect refract matrixCompMult outerProduct transpose determinant inverse lessThan "
  + "lessThanEqual greaterThan greaterThanEqual equal notEqual any all not dFdx dFdy fwidth").split(" "));
const RETURN_TYPES = new Set(["void", "bool", "int", "uint", "float", "vec2", "vec3", "vec4", "bvec2", "bvec3", "bvec4",
  "ivec2", "ivec3", "ivec4", "uvec2", "uvec3", "uvec4", "mat2", "mat3", "mat4"]);
/** What a renamed built-in's name gets (said back as the file's own name in errors). */
const OWN = "_user";

/** Built-in names the shader defines as functions of its own (`vec3 reflect(`). */
export function ownBuiltins(src) {
  const words = [...src.matchAll(TOKEN)].map((m) => m[0]).filter((t) => !/^\s+$/.test(t) && !/^\/[/*]/.test(t));
  const out = new Set();
  for (let i = 0; i + 2 < words.length; i++) {
    if (RETURN_TYPES.has(words[i]) && BUILTINS.has(words[i + 1]) && words[i + 2] === "(") out.add(words[i + 1]);
  }
  return out;
}

/** Each built-in name the shader defines for itself renamed NAME_user at every use (as
 * desktop GLSL's hiding would resolve them; comments untouched, lines kept). */
export function renameBuiltins(src) {
  const own = ownBuiltins(src);
  return own.size ? src.replace(TOKEN, (t) => (own.has(t) ? t + OWN : t)) : src;
}

/** `#version`/`#extension` lines blanked (line count kept). */
export const dropDirectives = (src) => src.replace(/^[ \t]*#[ \t]*(version|extension)\b[^\n]*/gm, "");

const GLSL_TYPE = { float: "float", bool: "bool", color: "vec3" };

/** One line of uniforms, one per parameter. */
export const uniformLine = (params) => params.map((p) => `uniform ${GLSL_TYPE[p.type]} ${p.name};`).join(" ") + "\n";

/** brdf(n, l, v) for the renderer, in the server's frame: X = +x projected onto the
 * tangent plane (+y where n is within FRAME_MIN of ±x, as the generated code does),
 * Y = N × X; the file's BRDF(L, V, N, X, Y) returns f (no cosine). */
export const WRAPPER = `
vec3 brdf(vec3 n, vec3 l, vec3 v) {
  vec3 t = vec3(1.0, 0.0, 0.0) - n.x * n;
  if (length(t) < 1e-3) t = vec3(0.0, 1.0, 0.0) - n.y * n;
  vec3 x = normalize(t);
  return BRDF(l, v, n, x, cross(n, x));
}
`;

/** The GLSL the renderer compiles for a parsed file, and where the file's shader lines
 * sit in it: {glsl, offset (glsl line − file line), limit (the file's last line)}. */
export function userGlsl(file, fileLines) {
  const uniforms = uniformLine(file.params);
  const body = floatLiterals(renameBuiltins(dropDirectives(file.shader)));
  return { glsl: uniforms + body + WRAPPER, offset: 1 - (file.shaderLine - 1), limit: fileLines };
}

/** A compile error's lines said for a user: an undeclared name is named as such. */
export function explain(lines) {
  return lines.map((x) => {
    const m = x.text.match(/'([A-Za-z_]\w*)'\s*:\s*undeclared identifier/);
    const own = x.text.replace(new RegExp(`\\b(\\w+)${OWN}\\b`, "g"), (w, name) => (BUILTINS.has(name) ? name : w));
    const text = m ? `${m[1]} is used but not declared (declare it under ::begin parameters, or in the shader)` : own;
    return x.line ? `line ${x.line}: ${text}` : text;
  }).join("\n");
}
