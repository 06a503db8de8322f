// The dashboard's login: name and password, as JSON (the server refuses forms); on success the
// session cookie is set and the dashboard opens.
"use strict";

document.getElementById("login").addEventListener("submit", async (event) => {
  event.preventDefault();
  const error = document.getElementById("login-error");
  error.textContent = "";
  const r = await fetch("/api/login", {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify({
      name: document.getElementById("name").value,
      password: document.getElementById("password").value,
    }),
  });
  if (r.ok) { location.assign("/"); return; }
  error.textContent = await r.text();
  document.getElementById("password").value = "";
});
