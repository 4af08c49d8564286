// /docs: Swagger UI over the app's own OpenAPI schema. A file rather than FastAPI's
// inline boot script, so /docs runs under the same Content-Security-Policy as the page.
window.ui = SwaggerUIBundle({
  url: "/openapi.json",
  dom_id: "#swagger-ui",
  deepLinking: true,
  presets: [SwaggerUIBundle.presets.apis],
  layout: "BaseLayout",
});
