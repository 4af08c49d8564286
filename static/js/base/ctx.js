/* The page's context: THE state and what the page learnt at boot. Its own module so that
 * the state's URL codec (state.js) and the pins (pins.js), which both read it, import it
 * and not each other: state.js imports pins.js, never the reverse.
 */
export const ctx = {
  state: {},             // THE state
  defaultState: {},
  views: [],             // GET /api/v1/views, in panel order
  panelList: [],         // every panel of the PANELS bar ({name, title, caption}): views.js panelList
  locals: new Map(),     // state key -> {view, field, input} of the panels' own fields
  embed: new URLSearchParams(location.search).get("embed") === "1",
  extraKeys: new Set(),  // query parameters another module declared (state.extra)
};
