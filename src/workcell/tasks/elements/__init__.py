"""What several tasks build from: the carrying expert that picks a box off the belt and
sets it down where its task says (:mod:`workcell.tasks.elements.expert`: box transfer's
zone, palletize's slots, sort's tables, shelve's shelf)."""
