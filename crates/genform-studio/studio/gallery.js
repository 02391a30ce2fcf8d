// The live gallery of a run: the latest picture of the population's distinct best, and a strip
// of the previous ones (as many as the server keeps) to click back to.

import { h, setChildren } from './dom.js';

/** The server keeps the last 6 live gallery pictures of a run. */
const KEPT = 6;

/** A gallery panel inside `container`; data-testids start with `testid`. */
export class Gallery {
  constructor(container, { testid = 'run-gallery' } = {}) {
    this.image = h('img', { class: 'gallery-image', testid: `${testid}-image`, alt: 'gallery of the distinct best', hidden: true });
    this.caption = h('span', { class: 'muted', testid: `${testid}-caption` });
    this.strip = h('div', { class: 'gallery-strip', testid: `${testid}-strip` });
    this.panel = h('div', { class: 'panel run-gallery', testid },
      h('div', { class: 'panel-title' }, 'Gallery: the population\u2019s distinct best ', this.caption), this.image, this.strip);
    container.append(this.panel);
    this.clear();
  }

  /** Forgets every picture. */
  clear() {
    setChildren(this.strip);
    this.image.removeAttribute('src');
    this.image.hidden = true;
    this.caption.textContent = 'Waiting for the first gallery…';
  }

  /** Shows the gallery picture of `generation` and keeps it in the strip. */
  show({ url, generation }) {
    if (!url) return;
    this.select(url, generation);
    if ([...this.strip.children].some((img) => img.dataset.url === url)) return;
    this.strip.append(h('img', { src: url, alt: `gallery, generation ${generation}`, title: `generation ${generation}`,
      dataset: { url }, onclick: () => this.select(url, generation) }));
    while (this.strip.children.length > KEPT) this.strip.firstChild.remove();
  }

  select(url, generation) {
    this.image.src = url;
    this.image.hidden = false;
    this.image.dataset.generation = String(generation);
    this.caption.textContent = `(generation ${generation})`;
  }
}
