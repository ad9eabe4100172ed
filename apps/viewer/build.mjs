// SPDX-License-Identifier: Apache-2.0
// Bundles src/main.js (three.js + 3d-tiles-renderer) into dist/viewer.js with esbuild, copies
// index.html, and writes dist/LICENSES.txt: the licence of every npm package in the bundle.
// Run `npm ci && npm run build` in apps/viewer after changing src/ or package.json; dist/ is
// committed so that building vdbmap needs neither npm nor the network.
import { build } from 'esbuild';
import { copyFileSync, mkdirSync, readFileSync, writeFileSync, existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname( fileURLToPath( import.meta.url ) );
const dist = join( here, 'dist' );
mkdirSync( dist, { recursive: true } );

const result = await build( {
	entryPoints: [ join( here, 'src/main.js' ) ],
	bundle: true,
	format: 'iife',
	target: 'es2020',
	minify: true,
	legalComments: 'none',
	metafile: true,
	outfile: join( dist, 'viewer.js' ),
	logLevel: 'warning',
} );
copyFileSync( join( here, 'index.html' ), join( dist, 'index.html' ) );

// Every package that contributed a file to the bundle, with its licence text.
const packages = new Map();
for ( const input of Object.keys( result.metafile.inputs ) ) {

	const m = input.match( /node_modules\/((?:@[^/]+\/)?[^/]+)\// );
	if ( m ) packages.set( m[ 1 ], join( here, 'node_modules', m[ 1 ] ) );

}
let text = 'Licences of the npm packages bundled into viewer.js (written by build.mjs).\n';
for ( const [ name, dir ] of [ ...packages ].sort() ) {

	const pkg = JSON.parse( readFileSync( join( dir, 'package.json' ), 'utf8' ) );
	const file = [ 'LICENSE', 'LICENSE.md', 'LICENSE.txt', 'license' ].map( f => join( dir, f ) ).find( existsSync );
	text += `\n==== ${ name } ${ pkg.version } (${ pkg.license }) ====\n`;
	text += file ? readFileSync( file, 'utf8' ) : `(no licence file in the package; package.json says ${ pkg.license })\n`;

}
writeFileSync( join( dist, 'LICENSES.txt' ), text );
console.log( `viewer.js ${ ( result.metafile.outputs[ Object.keys( result.metafile.outputs )[ 0 ] ].bytes / 1024 ).toFixed( 0 ) } KiB, packages: ${ [ ...packages.keys() ].join( ', ' ) }` );
