//! The timed-game engine (Peter 2005, chapters 2–5).
