"""The browser protocol: message models, the single source of the TypeScript types."""
